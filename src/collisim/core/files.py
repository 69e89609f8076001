"""Files collisim writes: under a temporary name beside the final one, renamed when complete.

A reader never sees half a file, an interrupted write leaves nothing behind, and the file gets the
permissions a plain open() would give it (mkstemp makes private files). Videos, PNG frames,
trajectories, collision maps, tables and charts are all written through here.
"""
from __future__ import annotations

import contextlib
import csv
import os
import tempfile
from pathlib import Path


def plain_permissions(name) -> None:
    """Give a file made by mkstemp/mkdtemp (private) the permissions a plain open() would give."""
    umask = os.umask(0)
    os.umask(umask)
    os.chmod(name, (0o777 if os.path.isdir(name) else 0o666) & ~umask)


def temporary_beside(path: Path, suffix: str) -> Path:
    """A new empty hidden file next to `path` (same file system, so the final rename is atomic)."""
    handle, name = tempfile.mkstemp(dir=Path(path).parent, prefix=f".{Path(path).stem}-", suffix=suffix)
    os.close(handle)
    plain_permissions(name)
    return Path(name)


@contextlib.contextmanager
def written_whole(path, what: str):
    """Yield a temporary path beside `path` to write to; when the block ends without error it
    becomes `path`, otherwise it is removed. A file system error (a missing folder, a folder in
    the file's place, no permission, a full disk) is a ValueError of one line naming `what` and
    `path`, never the temporary's name."""
    path = Path(path)
    try:
        temporary = temporary_beside(path, path.suffix or ".tmp")
    except OSError as error:
        raise ValueError(f"cannot write {what} {path}: {error.strerror or error}") from None
    try:
        yield temporary
        os.replace(temporary, path)   # onto a folder: IsADirectoryError, said as below
    except OSError as error:
        temporary.unlink(missing_ok=True)
        raise ValueError(f"cannot write {what} {path}: {error.strerror or error}") from None
    except BaseException:
        temporary.unlink(missing_ok=True)
        raise


def write_table(path, rows: list, columns, what: str = "table") -> Path:
    """Write rows (dicts) as a CSV file with the header `columns`, whole or not at all."""
    with written_whole(path, what) as temporary, open(temporary, "w", newline="", encoding="utf-8") as file:
        writer = csv.DictWriter(file, fieldnames=list(columns))
        writer.writeheader()
        writer.writerows(rows)
    return Path(path)


def write_text(path, text: str, what: str = "file") -> Path:
    """Write text (UTF-8), whole or not at all."""
    with written_whole(path, what) as temporary:
        temporary.write_text(text, encoding="utf-8")
    return Path(path)


def save_figure(figure, path, what: str = "chart") -> Path:
    """Save a matplotlib figure in the format its path's extension names, whole or not at all."""
    path = Path(path)
    with written_whole(path, what) as temporary:
        figure.savefig(temporary, format=path.suffix[1:] or "png")
    return path
