"""The plot scripts' side of the suite's one output policy (harness/common/output_file.hpp).

A figure is written only to a regular file this user may write or to a new name, never to a
directory, symlink, device, FIFO or socket, and never over one of the files being plotted
(recognised by device and inode, not by spelling). It goes to a temporary file beside the
target, is fsynced and renamed over it; on any failure the temporary file is removed and the
previous figure is left as it was.
"""
import os
import stat


class UnsafeOutput(Exception):
    """A target the policy refuses; the message names it and says why."""


def _kind(mode):
    for test, name in ((stat.S_ISDIR, "a directory"), (stat.S_ISLNK, "a symlink"), (stat.S_ISCHR, "a character device"),
                       (stat.S_ISBLK, "a block device"), (stat.S_ISFIFO, "a FIFO"), (stat.S_ISSOCK, "a socket")):
        if test(mode):
            return name
    return "not a regular file"


def identify(paths):
    """(device, inode, path) of each path that exists: the inputs an output must not be."""
    out = []
    for p in paths:
        try:
            st = os.stat(p)
        except OSError:
            continue
        out.append((st.st_dev, st.st_ino, p))
    return out


def check_target(path, inputs=()):
    """Raises UnsafeOutput if `path` may not be written under the policy."""
    try:
        st = os.lstat(path)
    except FileNotFoundError:
        st = None
    if st is not None:
        if not stat.S_ISREG(st.st_mode):
            raise UnsafeOutput(f"{path} exists and is {_kind(st.st_mode)}, not a regular file; figures are written only to a "
                               "regular file or a new name")
        for dev, ino, name in inputs:
            if (st.st_dev, st.st_ino) == (dev, ino):
                raise UnsafeOutput(f"{path} is the same file as the input {name}; writing it would destroy that input")
        if not os.access(path, os.W_OK, effective_ids=os.access in os.supports_effective_ids):
            raise UnsafeOutput(f"{path} exists and this user may not write it; it is left as it is")
    parent = os.path.dirname(path) or "."
    if not os.path.isdir(parent):
        raise UnsafeOutput(f"{path}: the directory '{parent}' does not exist")


def check_directory(directory):
    """Raises UnsafeOutput unless `directory` is a directory or can be created as one."""
    try:
        st = os.lstat(directory)
    except FileNotFoundError:
        parent = os.path.dirname(os.path.normpath(directory)) or "."
        if not os.path.isdir(parent):
            raise UnsafeOutput(f"{directory}: the directory '{parent}' does not exist")
        return
    if stat.S_ISLNK(st.st_mode):
        st = os.stat(directory)
    if not stat.S_ISDIR(st.st_mode):
        raise UnsafeOutput(f"{directory} exists and is {_kind(st.st_mode)}, not a directory; it holds several figures")


def _replace(path, inputs, fill):
    """Writes through a temporary file beside `path`: fill(file), fsync, rename over `path`."""
    check_target(path, inputs)
    tmp = f"{path}.tmp.{os.getpid()}"
    try:
        if os.path.lexists(tmp):
            os.unlink(tmp)  # a leftover of an earlier process with this pid, never anyone's data
        with open(tmp, "xb") as f:
            fill(f)
            f.flush()
            os.fsync(f.fileno())
        check_target(path, inputs)  # again: it may have changed while the content was made
        os.replace(tmp, path)
    except BaseException:
        try:
            os.unlink(tmp)
        except OSError:
            pass
        raise


def save_figure(fig, path, inputs=(), **savefig_args):
    """Saves a matplotlib figure to `path` under the policy (format from the extension)."""
    fmt = os.path.splitext(path)[1].lstrip(".") or "png"
    _replace(path, inputs, lambda f: fig.savefig(f, format=fmt, **savefig_args))


def write_text(path, text, inputs=()):
    """Writes `text` (UTF-8) to `path` under the policy."""
    _replace(path, inputs, lambda f: f.write(text.encode("utf-8")))
