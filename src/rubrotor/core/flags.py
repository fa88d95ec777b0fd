"""Compiler settings shared by the compiled kernels."""

__all__ = ["SAFE_FASTMATH"]

SAFE_FASTMATH = {"contract", "reassoc", "arcp", "nsz"}
"""LLVM fast-math flags that allow vectorisation but keep NaN and infinity semantics, so the
divergence checks ``not (d2 <= limit)`` still see a NaN."""
