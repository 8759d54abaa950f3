"""numba kernels of sweepcore: pure functions on float64 scalars and arrays.

Nothing here validates input or raises: the Python layer (``sweepcore.params``,
``sweepcore.sweep``) validates at the boundary, and every kernel reports failure
through the status codes of :mod:`sweepcore._kernels.codes`.
"""
