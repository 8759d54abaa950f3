"""Result files and resumable work.

* :mod:`.netcdf`: the CF netCDF4 result file, written atomically and block by block
  (:func:`write_netcdf`), read back (:func:`open_result`), checked (:func:`check_cf`).
* :mod:`.store`: the working store ``<path>.partial/`` of a sweep in progress
  (:class:`WorkingStore`): finished chunks with their SHA-256 and grid range, locked
  against a second sweep, checked again on resume.
* :mod:`.files`: what both share: which paths may become a result file
  (:func:`result_path`, decided before any work), temporary names beside a target,
  and write errors that name what was being written, where, and the space it needed.
"""
from .files import (check_flag, free_bytes, path_text, result_path, temporary_name,
                    write_failed)
from .netcdf import (check_cf, chunk_shape, estimated_bytes, netcdf_encoding,
                     open_result, write_netcdf)
from .store import DamagedChunkWarning, StoreBusy, StoreDamaged, WorkingStore

__all__ = ["check_cf", "chunk_shape", "estimated_bytes", "netcdf_encoding", "open_result",
           "write_netcdf", "check_flag", "free_bytes", "path_text", "result_path",
           "temporary_name", "write_failed",
           "DamagedChunkWarning", "StoreBusy", "StoreDamaged", "WorkingStore"]
