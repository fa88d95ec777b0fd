"""A sphinx-gallery image scraper for the figures rubrotor's plotting functions return.

Those figures are plain :class:`matplotlib.figure.Figure` objects, never registered with pyplot
(the package changes no global state), so the matplotlib scraper does not see them. This one
saves every such figure an example holds in a variable, once.
"""

from __future__ import annotations


def package_figures(block, block_vars, gallery_conf):
    """Save the example's unregistered figures; return their reST (see sphinx-gallery scrapers)."""
    from matplotlib.figure import Figure
    from sphinx_gallery.scrapers import figure_rst

    globals_ = block_vars["example_globals"]
    seen = globals_.setdefault("__rubrotor_scraped__", set())
    paths = []
    for value in list(globals_.values()):
        pyplot_figure = hasattr(value, "number")  # pyplot numbers the figures it manages
        if isinstance(value, Figure) and not pyplot_figure and id(value) not in seen:
            seen.add(id(value))
            path = next(block_vars["image_path_iterator"])
            value.savefig(path, dpi=100)
            paths.append(path)
    return figure_rst(paths, gallery_conf["src_dir"])
