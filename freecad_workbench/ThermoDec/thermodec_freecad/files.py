"""Atomic text output for the workbench's own files (model.json, result JSON).

The same rules as the core's writer: an exclusive temporary with an unpredictable name beside
the output (never a planted symlink), flushed, then renamed into place; an existing output keeps
its permission bits; an existing output that is not a regular file is refused.
"""
import os
import stat
import tempfile

from .errors import ThermoDecError


def atomic_write_text(path, text):
    """Writes `text` (UTF-8) to `path` atomically. Raises ThermoDecError naming the path."""
    folder = os.path.dirname(os.path.abspath(path)) or "."
    mode = None
    try:
        st = os.lstat(path)
        if not stat.S_ISREG(st.st_mode):
            raise ThermoDecError("%s: exists and is not a regular file; not replaced" % path)
        mode = stat.S_IMODE(st.st_mode)
    except FileNotFoundError:
        pass
    fd, tmp = tempfile.mkstemp(prefix="." + os.path.basename(path) + ".tmp-", dir=folder)
    try:
        with os.fdopen(fd, "w", encoding="utf-8") as f:
            f.write(text)
            f.flush()
            os.fsync(f.fileno())
        if mode is None:
            umask = os.umask(0)
            os.umask(umask)
            mode = 0o666 & ~umask
        os.chmod(tmp, mode)
        os.replace(tmp, path)
    except BaseException:
        try:
            os.unlink(tmp)
        except OSError:
            pass
        raise
