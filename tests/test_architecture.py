"""The package's layering: core kernels import nothing of the user-facing world."""

import ast
from pathlib import Path

import rubrotor

CORE = Path(rubrotor.__file__).parent / "core"
# collections: namedtuples, the named structures compiled kernels take; enum: the status mirror
ALLOWED = {"math", "numpy", "numba", "rubrotor", "__future__", "collections", "enum"}


def test_core_imports_only_numpy_numba_and_core():
    """Checks every import statement of rubrotor.core (the same rule import-linter enforces)."""
    for path in CORE.glob("*.py"):
        tree = ast.parse(path.read_text())
        for node in ast.walk(tree):
            if isinstance(node, ast.Import):
                names = [a.name for a in node.names]
            elif isinstance(node, ast.ImportFrom):
                names = [node.module or ""]
            else:
                continue
            for name in names:
                top = name.split(".")[0]
                assert top in ALLOWED, f"{path.name} imports {name}"
                if top == "rubrotor":
                    assert name.startswith("rubrotor.core"), f"{path.name} imports {name}"


def test_import_linter_contract_is_kept():
    from importlinter import cli

    assert (
        cli.lint_imports(config_filename=str(Path(rubrotor.__file__).parents[2] / "pyproject.toml"))
        == 0
    )


def test_layers_contract_covers_every_folder():
    """The import-linter ``layers`` contract of pyproject.toml places every folder and top-level
    module of the package (a second check beside import-linter's own ``exhaustive`` one: the
    files on disk against the names in the contract)."""
    import tomllib

    config = tomllib.loads((Path(rubrotor.__file__).parents[2] / "pyproject.toml").read_text())
    layers = [c for c in config["tool"]["importlinter"]["contracts"] if c["type"] == "layers"]
    assert len(layers) == 1, "one layers contract"
    contract = layers[0]
    assert contract["containers"] == ["rubrotor"] and contract["exhaustive"] is True
    named = {n.strip(" ()") for layer in contract["layers"] for n in layer.split("|")}
    root = Path(rubrotor.__file__).parent
    children = {p.stem for p in root.glob("*.py") if p.stem != "__init__"}
    children |= {p.name for p in root.iterdir() if (p / "__init__.py").is_file()}
    assert children <= named, sorted(children - named)


MAX_FUNCTION_LINES = 120


def test_no_function_over_120_lines_outside_core():
    """Every function outside the compiled kernels of rubrotor.core is short enough to read.

    Lines are counted from the AST (``def`` to the last line of the body, docstring included).
    """
    root = Path(rubrotor.__file__).parent
    long = []
    for path in sorted(root.rglob("*.py")):
        if path.is_relative_to(CORE):
            continue
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef):
                n = node.end_lineno - node.lineno + 1
                if n > MAX_FUNCTION_LINES:
                    long.append(f"{path.relative_to(root)}:{node.lineno} {node.name} ({n} lines)")
    assert not long, long


def test_no_import_cycle_between_modules():
    """The import graph of the submodules (function-level imports included) has no cycle.

    The package root ``rubrotor`` (the facade re-exporting the public API, also read for
    ``__version__``) is left out; every other module must sit in one-way layers.
    """
    import graphlib

    import grimp

    graph = grimp.build_graph("rubrotor")
    edges = {
        m: {d for d in graph.find_modules_directly_imported_by(m) if d != "rubrotor"}
        for m in graph.modules
        if m != "rubrotor"
    }
    try:
        tuple(graphlib.TopologicalSorter(edges).static_order())
    except graphlib.CycleError as exc:
        raise AssertionError(f"import cycle: {' -> '.join(exc.args[1])}") from None


def test_scenario_kind_is_decided_once():
    """No module outside ``rubrotor.scenario`` tests which tables a scenario had (``.shaft is
    None``, ``.rotor is not None``, ``.engine is None``, ...): every verb asks the Model
    (:class:`rubrotor.modelling.Model`)."""
    import re

    root = Path(rubrotor.__file__).parent
    pattern = re.compile(r"\.(shaft|rotor|engine) is (not )?None")
    found = [
        f"{path.relative_to(root)}:{i}"
        for path in sorted(root.rglob("*.py"))
        if not path.is_relative_to(root / "scenario")
        for i, line in enumerate(path.read_text().splitlines(), 1)
        if pattern.search(line)
    ]
    assert not found, found


# what testing the rotor's kind looks like: the old Model's flags, the kind's fields compared,
# the scenario's own refusal of other engines, an isinstance test on a rotor builder's type
KIND_TESTS = (
    r"\.fe_rotor\b",
    r"\.model\.(general|rotor|engine|spin|formulation|features)\b",
    r"\.rotor\s*(==|!=)",
    r"require_seed_engine\(",
    r"isinstance\([^)]*\b(Rotor|Shaft|LinearSystem)\b",
)


def test_only_the_model_tests_the_rotors_kind():
    """No module outside the Model (:mod:`rubrotor.modelling`, and the scenario package that
    classifies a file once, :mod:`rubrotor.scenario.kind`) tests what kind of rotor it has:
    the verbs ask the Model's decisions (``runner``, ``maps``, ``linear``) and builders
    (``linear_system``, ``forces``, ``speed_law``). Checked line by line on the source."""
    import re

    root = Path(rubrotor.__file__).parent
    pattern = re.compile("|".join(KIND_TESTS))
    found = [
        f"{path.relative_to(root)}:{i}: {line.strip()}"
        for path in sorted(root.rglob("*.py"))
        if not path.is_relative_to(root / "scenario") and path != root / "modelling.py"
        for i, line in enumerate(path.read_text().splitlines(), 1)
        if pattern.search(line)
    ]
    assert not found, found
    # the pattern does catch what it is meant to (a test that can fail)
    assert pattern.search("if scenario.model.fe_rotor:")
    assert pattern.search("elif isinstance(obj, Shaft):")


def test_no_contact_law_tested_by_name_outside_forces():
    """Which law a contact is stays behind its term (``rubrotor.forces``): no ``law ==`` or
    ``law !=`` comparison anywhere else in the package (an AST check, comments and strings
    excluded). The engine, the scenario loader, sweeps and analyses ask the law's term object."""
    root = Path(rubrotor.__file__).parent
    forces = root / "forces"
    found = []
    for path in sorted(root.rglob("*.py")):
        if path.is_relative_to(forces):
            continue
        for node in ast.walk(ast.parse(path.read_text())):
            if not isinstance(node, ast.Compare):
                continue
            if not any(isinstance(op, ast.Eq | ast.NotEq) for op in node.ops):
                continue
            for side in (node.left, *node.comparators):
                name = side.attr if isinstance(side, ast.Attribute) else getattr(side, "id", "")
                if name == "law":
                    found.append(f"{path.relative_to(root)}:{node.lineno}")
    assert not found, found


def test_engine_kernels_take_named_structures():
    """The compiled kernels of the general engine, its adaptive stepper, the free-speed stepper
    and the contact law take at most 8 positional arguments: the rest travels in named
    structures (``rubrotor.engine.structs``) or tuples unpacked at the top of the kernel."""
    wide = []
    for name in ("engine.py", "engine_adaptive.py", "spin.py", "contact.py"):
        for node in ast.parse((CORE / name).read_text()).body:
            if not isinstance(node, ast.FunctionDef):
                continue
            if not any("njit" in ast.unparse(d) for d in node.decorator_list):
                continue
            if len(node.args.args) > 8:
                wide.append(f"{name}:{node.name} ({len(node.args.args)})")
    assert not wide, wide


def test_one_status_enumeration():
    """Every compiled run reports a code of ``rubrotor.core.status``; no module defines its own.

    The codes are distinct, each has a message, and no other module assigns an integer to a
    status name (an alias imported from the enumeration is fine).
    """
    from rubrotor.core import status

    codes = [getattr(status, name) for name in status.Status.__members__]
    assert sorted(codes) == list(range(len(status.MESSAGES)))
    for code in codes:
        assert status.Status(code).message == status.MESSAGES[code] == status.message(code)
    names = set(status.Status.__members__) | {
        "NEWTON_FAILED", "STATUS", "STATUS_NAMES", "_STATUS", "SPIN_OK", "SPIN_DIVERGED",
        "SPIN_STEP_TOO_SMALL", "SPIN_MAX_STEPS",
    }  # fmt: skip
    root = Path(rubrotor.__file__).parent
    own = []
    for path in sorted(root.rglob("*.py")):
        if path == CORE / "status.py":
            continue
        for node in ast.parse(path.read_text()).body:
            targets = node.targets if isinstance(node, ast.Assign) else []
            for t in targets:
                elts = t.elts if isinstance(t, ast.Tuple) else [t]
                bad = [e.id for e in elts if isinstance(e, ast.Name) and e.id in names]
                if bad and not isinstance(node.value, ast.Call):
                    own.append(f"{path.relative_to(root)}:{node.lineno} {bad}")
    assert not own, own


MAX_KERNEL_ARGS = 8
# Kernels allowed more positional arguments: none since the force terms landed (issue 29 item 1
# converted the general engine's and the free-speed integrator's kernels to named structures).
KERNEL_ARGS_ALLOWED: dict[str, set[str]] = {}


def _is_compiled(node: ast.FunctionDef) -> bool:
    for dec in node.decorator_list:
        target = dec.func if isinstance(dec, ast.Call) else dec
        name = target.attr if isinstance(target, ast.Attribute) else getattr(target, "id", "")
        if name in {"njit", "jit", "vectorize", "guvectorize", "cfunc", "generated_jit"}:
            return True
    return False


def test_compiled_kernels_take_named_structures():
    """No compiled kernel of rubrotor.core takes more than 8 positional arguments: what a kernel
    reads comes in named tuples (or tuples of related arrays), not long positional lists."""
    long = []
    for path in sorted(CORE.glob("*.py")):
        allowed = KERNEL_ARGS_ALLOWED.get(path.name, set())
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, ast.FunctionDef) and _is_compiled(node):
                n = len(node.args.posonlyargs) + len(node.args.args)
                if node.args.vararg is not None:
                    n = MAX_KERNEL_ARGS + 1  # *args hides the count
                if n > MAX_KERNEL_ARGS and node.name not in allowed:
                    long.append(f"{path.name}:{node.lineno} {node.name} ({n} arguments)")
    assert not long, long
    # the allow-list names only kernels that exist and still need it
    for name, kernels in KERNEL_ARGS_ALLOWED.items():
        tree = ast.parse((CORE / name).read_text())
        defined = {n.name: n for n in ast.walk(tree) if isinstance(n, ast.FunctionDef)}
        for k in kernels:
            if k in defined:
                args = defined[k].args
                assert len(args.posonlyargs) + len(args.args) > MAX_KERNEL_ARGS, (name, k)


def test_one_stepper_table():
    """Every engine's steppers are named, with their orders, in the one table
    ``rubrotor.engine.settings.STEPPERS``; the Integrator's methods read their orders there."""
    from rubrotor.engine import driver, settings, shaft_steppers

    table = settings.STEPPERS
    general = getattr(driver, "FACTORIES", None) or driver.STEPPERS
    for engine, factories in (("shaft", shaft_steppers.FACTORIES), ("general", general)):
        for name in factories:
            assert name in table and engine in table[name].engines, (engine, name)
    for name, spec in table.items():
        assert spec.order in (2, 3, 4) and spec.engines, name
    assert settings.METHODS == {m: table[m].order for m in settings.METHODS}
    assert set(settings.SHAFT_INITIAL_STATES) <= set(settings.INITIAL_STATES)


FORCE_KERNELS = {"_law", "contact_force", "contact_force_jac", "contact_force_jac_exact",
                 "solve_contact", "film_sums", "film_force", "film_force_jac", "magnet_force"}
"""The compiled force kernels of the terms: called only through the dispatch."""


def test_force_kernels_called_only_through_the_dispatch():
    """A term's force kernel is called by its own module, by ``rubrotor.forces`` and by the one
    dispatch ``core/terms.py``; the engine, orbits, linear analyses and studies call
    ``rubrotor.core.terms`` (``term``, ``term_jac``, ``term_jac_exact``, ``term_force``) and never
    name a law or a film. The shaft's own complex single-contact Newton (``solve_contact``,
    ``core/integrate.py``) is the one exception left, listed here."""
    root = Path(rubrotor.__file__).parent
    allowed = {root / "core" / n for n in ("contact.py", "film.py", "amb.py", "terms.py")}
    allowed |= {root / "core" / "integrate.py"}  # solve_contact: the seed shaft's exact route
    found = []
    for path in sorted(root.rglob("*.py")):
        if path in allowed or path.is_relative_to(root / "forces"):
            continue
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, ast.Call):
                f = node.func
                name = f.attr if isinstance(f, ast.Attribute) else getattr(f, "id", "")
                if name in FORCE_KERNELS:
                    found.append(f"{path.relative_to(root)}:{node.lineno} {name}")
    assert not found, found
