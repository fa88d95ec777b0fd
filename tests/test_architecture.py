"""The package's layering: core kernels import nothing of the user-facing world."""

import ast
from pathlib import Path

import rubrotor

CORE = Path(rubrotor.__file__).parent / "core"
# collections: namedtuples, the named structures compiled kernels take
ALLOWED = {"math", "numpy", "numba", "rubrotor", "__future__", "collections"}


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
