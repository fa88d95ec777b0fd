"""The command line, ``rubrotor VERB SCENARIO [options]`` (:mod:`rubrotor.cli.app`: the verb table and ``main``)."""


def __getattr__(name):
    import importlib

    module = importlib.import_module("rubrotor.cli.app")

    try:
        return getattr(module, name)
    except AttributeError:
        raise AttributeError(f"module 'rubrotor.cli' has no attribute {name!r}") from None
