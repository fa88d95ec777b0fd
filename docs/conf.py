"""Sphinx configuration of the rubrotor documentation site.

Build (warnings are errors, cross-references nitpicky), the README's command::

    python -m pip install -e ".[docs]" && python -m sphinx -W -n --keep-going -b html docs docs/_build/html

The build first runs the tutorial's and how-to pages' commands (``docs/run_pages.py``), whose
figures and output the pages show: the pages not yet run, or whose folder changed since they
last passed (a fresh clone runs them all; ``RUBROTOR_DOCS_PAGES=all`` runs every page, ``skip``
none). A page whose commands fail is a build warning, so an error with ``-W``. Running them here
rather than as a second command keeps the README's one command whole: it was the cause of a
fresh clone's build failing on the figures it had not made.

Intersphinx inventories of NumPy, SciPy, xarray and matplotlib are fetched only when
``RUBROTOR_DOCS_INTERSPHINX=1`` (the build machines of this project have no web access); without
them, references into those projects are accepted unresolved (``nitpick_ignore_regex`` below),
while every reference into rubrotor itself must resolve.
"""

from __future__ import annotations

import os
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "src"))
sys.path.insert(0, str(Path(__file__).parent))

import cli_reference  # noqa: E402
import run_pages  # noqa: E402

import rubrotor  # noqa: E402
from rubrotor.scenario.schema import markdown_table  # noqa: E402

project = "rubrotor"
author = "rubrotor developers"
copyright = "2026, rubrotor developers"  # noqa: A001 - Sphinx's name
version = release = rubrotor.__version__

extensions = [
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "sphinx.ext.intersphinx",
    "sphinx.ext.mathjax",
    "numpydoc",
    "myst_parser",
    "sphinx_gallery.gen_gallery",
    "sphinx-mathjax-offline",  # MathJax 3 copied into _static: equations render with no network
]
source_suffix = {".rst": "restructuredtext", ".md": "markdown"}
exclude_patterns = ["_build", "_generated", "_pages", "auto_examples/*.ipynb", "auto_examples/*.py", "**/*.zip"]
myst_heading_anchors = 3

autosummary_generate = True
templates_path = ["_templates"]
autosummary_ignore_module_all = False
autodoc_typehints = "none"
autodoc_default_options = {"members": True, "inherited-members": False}
numpydoc_show_class_members = False
numpydoc_xref_param_type = False
numpydoc_validation_checks: set[str] = set()

intersphinx_mapping = (
    {
        "python": ("https://docs.python.org/3", None),
        "numpy": ("https://numpy.org/doc/stable", None),
        "scipy": ("https://docs.scipy.org/doc/scipy", None),
        "xarray": ("https://docs.xarray.dev/en/stable", None),
        "matplotlib": ("https://matplotlib.org/stable", None),
    }
    if os.environ.get("RUBROTOR_DOCS_INTERSPHINX") == "1"
    else {}
)
nitpicky = True
nitpick_ignore_regex = [
    # other projects' objects: resolved by intersphinx where it is enabled (see above)
    (r"py:.*", r"(numpy|np|scipy|xarray|xr|matplotlib|dask|distributed|zarr|pathlib|os)\..*"),
    (r"py:.*", r"(ndarray|Dataset|DataArray|Figure|Axes|Path|PathLike|Mapping|Sequence)"),
    # builtins named in signatures and numpydoc type fields
    (r"py:.*", r"(int|float|complex|str|bool|dict|list|tuple|callable|None|object|optional)"),
]

html_theme = "pydata_sphinx_theme"
html_title = f"rubrotor {release}"
html_theme_options = {
    "navigation_with_keys": False,
    "show_toc_level": 2,
    "footer_start": ["copyright"],
}
html_static_path = ["_static"]
html_css_files = ["rubrotor.css"]  # code wraps instead of scrolling sideways

sphinx_gallery_conf = {
    "image_scrapers": ("matplotlib", "gallery_scraper.package_figures"),
    "examples_dirs": str(ROOT / "examples"),
    "gallery_dirs": "auto_examples",
    "filename_pattern": r"/plot_",
    "download_all_examples": False,
    "remove_config_comments": True,
    "within_subsection_order": "FileNameSortKey",
}


_generated = Path(__file__).parent / "_generated"
_generated.mkdir(exist_ok=True)
for _name, _text in (
    ("schema.md", markdown_table()),  # reference/scenarios.md's key tables (scenario.schema)
    ("cli.md", cli_reference.markdown()),  # reference/cli.md: every verb's --help
):
    _target = _generated / _name
    if not _target.exists() or _target.read_text() != _text:
        _target.write_text(_text)


def _run_pages(app) -> None:
    """Run the page scripts the build needs (module docstring); a failing one is a warning."""
    from sphinx.util import logging

    mode = os.environ.get("RUBROTOR_DOCS_PAGES", "stale")
    if mode not in ("stale", "all", "skip"):
        raise ValueError(f"RUBROTOR_DOCS_PAGES={mode!r}: one of 'stale' (default), 'all', 'skip'")
    if mode == "skip":
        return
    found = run_pages.scripts()
    names = [n for n, s in found.items() if mode == "all" or run_pages.stale(n, s)]
    for name in names:
        if not run_pages.run(name, found[name]):
            logging.getLogger(__name__).warning(
                "page %s: its commands failed (docs/_pages/%s/output.txt)", name, name
            )


def setup(app):
    app.connect("builder-inited", _run_pages)
