"""The zarr store of a risk analysis: per-sample inputs and outputs, written chunk by chunk.

Arrays (zarr format 2, readable with ``xarray.open_zarr``): ``inputs (sample, key)`` (the
keys' units), per-sample outputs over ``(sample, speed)`` or ``(sample, block)``, and ``done
(chunk)``, set to 1 after a chunk's values are written, with SIGINT held (as sweeps do), so
a killed run leaves a valid store and the same run again computes only the missing chunks.
Nothing of size N is kept in memory: every chunk goes straight to disk.
"""

from __future__ import annotations

import json
import os
import shutil
import tempfile
from pathlib import Path

import numpy as np

from rubrotor.errors import InputError

__all__ = ["RiskStore"]


def _create(group, name, shape, chunks, dtype, fill, dims, attrs):
    make = getattr(group, "create_array", None) or group.create_dataset  # zarr 3 / zarr 2
    arr = make(name, shape=shape, chunks=chunks, dtype=dtype, fill_value=fill)
    arr.attrs.update({"_ARRAY_DIMENSIONS": list(dims), **attrs})
    return arr


class RiskStore:
    """A risk analysis' store (see the module docstring).

    Parameters
    ----------
    path : path-like
        The zarr directory.
    definition : dict
        The analysis (scenario, keys, distributions, N, seed, ...); a store recording another
        definition is refused by name.
    layout : dict
        ``name -> (dims, dtype, fill, attrs)`` of the per-sample arrays.
    sizes : dict
        Dimension sizes (``sample``, ``speed``, ``key``, ...).
    chunk : int
        Samples per chunk.
    coords : dict
        ``name -> (values, attrs)`` of 1-D coordinates written once.
    """

    def __init__(self, path, definition: dict, layout: dict, sizes: dict, chunk: int,
                 coords: dict) -> None:  # fmt: skip
        import zarr

        self.path, self.chunk = Path(path), int(chunk)
        text = json.dumps(definition, sort_keys=True)
        n_chunks = -(-sizes["sample"] // self.chunk)
        if self.path.exists():
            try:
                self.group = zarr.open_group(str(self.path), mode="r+")
                recorded = self.group.attrs.get("risk_definition")
            except Exception as exc:  # noqa: BLE001 - any unreadable store is a user error here
                raise InputError("store", str(path), f"a risk store ({exc})") from None
            if recorded != text:
                raise InputError("store", str(path), "a store of the same risk analysis to "
                                 "resume; use another --out or delete it")  # fmt: skip
            return
        self.path.absolute().parent.mkdir(parents=True, exist_ok=True)
        tmp = Path(tempfile.mkdtemp(prefix=f".{self.path.name}.", dir=self.path.absolute().parent))
        try:
            kw = {"zarr_format": 2} if int(zarr.__version__.split(".")[0]) >= 3 else {}
            g = zarr.open_group(str(tmp / "store"), mode="w", **kw)
            for name, (values, attrs) in coords.items():
                a = _create(g, name, (len(values),), (max(1, len(values)),),
                            np.asarray(values).dtype, None, (name,), attrs)  # fmt: skip
                a[:] = np.asarray(values)
            for name, (dims, dtype, fill, attrs) in layout.items():
                shape = tuple(sizes[d] for d in dims)
                chunks = tuple(self.chunk if d == "sample" else max(1, sizes[d]) for d in dims)
                _create(g, name, shape, chunks, dtype, fill, dims, attrs)
            _create(g, "done", (n_chunks,), (max(1, n_chunks),), "i1", 0, ("chunk",),
                    {"long_name": "1 when the chunk of samples is written"})  # fmt: skip
            g.attrs["risk_definition"] = text
            os.rename(tmp / "store", self.path)
        except OSError:
            raise InputError("store", str(path), "a store no other run is creating") from None
        finally:
            shutil.rmtree(tmp, ignore_errors=True)
        self.group = zarr.open_group(str(self.path), mode="r+")

    def done(self) -> np.ndarray:
        """Mask of the chunks already written."""
        return np.asarray(self.group["done"][:]).astype(bool)

    def write(self, index: int, values: dict) -> None:
        """Write chunk ``index`` (``name -> array`` with the chunk's samples first), then mark it."""
        from rubrotor.sweeps.sweep import _deferred_interrupt

        a = index * self.chunk
        with _deferred_interrupt():
            for name, v in values.items():
                self.group[name][a : a + len(v)] = v
            self.group["done"][index] = 1

    def read(self, name: str, index: int, count: int) -> np.ndarray:
        """The values of ``name`` for ``count`` samples of chunk ``index``."""
        a = index * self.chunk
        return np.asarray(self.group[name][a : a + count])

    def attrs(self, **values) -> None:
        """Record attributes on the store (JSON-serialisable)."""
        self.group.attrs.update(values)
