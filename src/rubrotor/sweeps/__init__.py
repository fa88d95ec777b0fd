"""Parameter sweeps: grids of scenario keys run in a resumable zarr store, rub regimes and run
metrics (:mod:`rubrotor.sweeps.regimes`, the one definition), and state-carrying up/down sweeps
(:mod:`rubrotor.sweeps.follow`). :mod:`rubrotor.sweeps.sweep` imports zarr and dask lazily.
"""
