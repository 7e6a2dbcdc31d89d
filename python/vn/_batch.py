"""Batches: many files into one folder, for `vn.convert` with ``out_dir``
and `vn.dask`. libvnio's vn_io_batch_plan says which file goes where and
refuses what ``vnconvert --out-dir`` refuses; each file is then one
vn_io_convert set as vnconvert's batch sets it, so the outputs are
vnconvert's byte for byte.
"""

import os
import sys
import time

from ._binding import Error

# Set per file (a batch's own: not keywords of convert).
_PER_FILE = ("threads", "input_format", "format", "stats")


class FileResult:
    """One file of a batch.

    Attributes
    ----------
    input, output : str
        The paths, as planned.
    status : str
        "converted", "failed" or "done" (skipped: the output was there,
        not older than the input, and overwriting was not asked for).
    message : str or None
        Why it failed: vnconvert's one-line error, naming the file.
    triangles : int
        Triangles written.
    input_bytes, output_bytes : int
        File sizes (a .gltf output's buffers and images not counted).
    seconds : float
        The conversion's time where it ran.
    warnings : list of str
    worker : str or None
        Where it ran (vn.dask: the worker's address).
    """

    __slots__ = ("input", "output", "status", "message", "triangles", "input_bytes", "output_bytes", "seconds",
                 "warnings", "worker")

    def __init__(self, input, output, status, message=None, triangles=0, input_bytes=0, output_bytes=0,
                 seconds=0.0, warnings=(), worker=None):
        self.input, self.output, self.status, self.message = input, output, status, message
        self.triangles, self.input_bytes, self.output_bytes = triangles, input_bytes, output_bytes
        self.seconds, self.warnings, self.worker = seconds, list(warnings), worker

    def __getstate__(self):
        return {k: getattr(self, k) for k in self.__slots__}

    def __setstate__(self, state):
        for k, v in state.items():
            setattr(self, k, v)

    def __repr__(self):
        return "vn.FileResult(%s)" % ", ".join("%s=%r" % (k, getattr(self, k)) for k in self.__slots__)


class Batch:
    """What a batch did: every file's `FileResult`, in the plan's order.

    Attributes
    ----------
    files : list of FileResult
    converted, failed, done : list of FileResult
        By status.
    skipped : int
        Folder entries of no format vn reads, passed over.
    unentered : int
        Subfolders not entered (without ``recursive``).
    triangles, input_bytes, output_bytes : int
        Over the files converted.
    seconds : float
        The whole batch, planning included.
    """

    def __init__(self, files, skipped, unentered, seconds):
        self.files, self.skipped, self.unentered, self.seconds = files, skipped, unentered, seconds

    @classmethod
    def of_plan(cls, planned, results, start):
        """The Batch of plan(...)'s (files, skipped, unentered), from the
        results in any order (FileResult, one per file), timed from start."""
        files, skipped, unentered = planned
        order = {f[1]: i for i, f in enumerate(files)}
        return cls(sorted(results, key=lambda r: order[r.output]), skipped, unentered, time.perf_counter() - start)

    def _with(self, status):
        return [f for f in self.files if f.status == status]

    converted = property(lambda self: self._with("converted"))
    failed = property(lambda self: self._with("failed"))
    done = property(lambda self: self._with("done"))
    triangles = property(lambda self: sum(f.triangles for f in self.converted))
    input_bytes = property(lambda self: sum(f.input_bytes for f in self.converted))
    output_bytes = property(lambda self: sum(f.output_bytes for f in self.converted))

    def summary(self):
        """One line: "3 files converted, 1 failed, 2 done before; 12,288
        triangles, 1.2 MB read, 0.9 MB written in 0.41 s (7.3 files/s)"."""
        n = len(self.converted)
        parts = ["%d %s converted" % (n, "file" if n == 1 else "files")]
        if self.failed:
            parts.append("%d failed" % len(self.failed))
        if self.done:
            parts.append("%d done before (skipped)" % len(self.done))
        if self.skipped:
            parts.append("%d skipped (not a format vn reads)" % self.skipped)
        if self.unentered:
            parts.append("%d %s not entered (recursive)" % (self.unentered,
                                                               "folder" if self.unentered == 1 else "folders"))
        rate = n / self.seconds if self.seconds > 0 else 0.0
        return "%s; %s triangles, %.1f MB read, %.1f MB written in %.2f s (%.1f files/s)" % (
            ", ".join(parts), format(self.triangles, ","), self.input_bytes / 1e6, self.output_bytes / 1e6,
            self.seconds, rate)

    def __repr__(self):
        return "<vn.Batch: %s>" % self.summary()


def is_done(input, output):
    """Whether output is there from an earlier run: it exists, is not the
    input, and is not older than it. Outputs are written atomically (a
    .gltf after its buffers and images), so one that exists is whole."""
    try:
        out, src = os.stat(output), os.stat(input)
    except OSError:
        return False
    return (out.st_dev, out.st_ino) != (src.st_dev, src.st_ino) and out.st_mtime_ns >= src.st_mtime_ns


def plan(io, inputs, out_dir, method, recursive, options):
    """(files, skipped, unentered) of vn_io_batch_plan, the options checked
    as vnconvert checks them; the output folders are made."""
    if isinstance(inputs, (str, bytes, os.PathLike)):
        inputs = [inputs]
    if options.get("stats"):
        raise Error("stats is for one file: a batch's result has the counts of every file instead")
    return io.plan([os.fspath(p) for p in inputs], os.fspath(out_dir), recursive, io.options(method, options))


def convert_file(input, output, input_format, output_format, method, options, threads=1):
    """Converts one planned file as vnconvert's batch does; a failure comes
    back in the result, not raised. Runs where it is called (a Dask worker
    for vn.dask), with the vn package there."""
    from . import _convert, library  # on a worker: its own vn
    start = time.perf_counter()
    try:
        io = _convert.io_library(library().path)
        o = io.options(method, {k: v for k, v in options.items() if k not in _PER_FILE})
        o.input_format, o.output_format = input_format.encode(), output_format.encode()
        o.threads = max(1, int(threads))
        o.image_names_from_output = o.ignore_misfits = 1
        r = io.convert(input, output, o)
        return FileResult(input, output, "converted", triangles=r.triangles, input_bytes=_size(input),
                          output_bytes=_size(output), seconds=time.perf_counter() - start, warnings=r.warnings)
    except Error as e:
        return FileResult(input, output, "failed", message=str(e), seconds=time.perf_counter() - start)


def _size(path):
    try:
        return os.path.getsize(path)
    except OSError:
        return 0


class Progress:
    """progress=None: a bar on stderr when it is a terminal (after a second,
    as vnconvert draws it); False: nothing; a callable: called as
    ``progress(done, total, result)`` after each file."""

    def __init__(self, progress, total):
        self.total, self.done, self.start, self.drawn = total, 0, time.monotonic(), False
        self.call = progress if callable(progress) else None
        self.bar = progress is None and sys.stderr is not None and sys.stderr.isatty()

    def advance(self, result):
        self.done += 1
        if self.call:
            self.call(self.done, self.total, result)
        if self.bar and time.monotonic() - self.start >= 1:
            filled = 30 * self.done // max(self.total, 1)
            sys.stderr.write("\r[%s%s] %d/%d files" % ("=" * filled, " " * (30 - filled), self.done, self.total))
            sys.stderr.flush()
            self.drawn = True

    def clear(self):
        """Takes the bar off the line (before other output, and at the end)."""
        if self.drawn:
            sys.stderr.write("\r\033[K")
            sys.stderr.flush()
            self.drawn = False


def split(files, overwrite):
    """(results of the files done before, the files to convert)."""
    if overwrite:
        return [], list(files)
    done, todo = [], []
    for f in files:
        if is_done(f[0], f[1]):
            done.append(FileResult(f[0], f[1], "done"))
        else:
            todo.append(f)
    return done, todo


def run_local(io, inputs, out_dir, method, recursive, overwrite, progress, options):
    """vn.convert's batch: the planned files on a pool of threads here (the
    GIL is released while a file converts)."""
    from concurrent.futures import ThreadPoolExecutor, as_completed
    start = time.perf_counter()
    planned = plan(io, inputs, out_dir, method, recursive, options)
    done, todo = split(planned[0], overwrite)
    jobs = int(options.get("threads") or os.cpu_count() or 1)
    # Files side by side, one thread each; the cores fewer files leave go to those.
    threads = max(1, jobs // max(len(todo), 1))
    bar = Progress(progress, len(todo))
    results = list(done)
    try:
        with ThreadPoolExecutor(max_workers=jobs) as pool:
            futures = [pool.submit(convert_file, *f, method, options, threads) for f in todo]
            for f in as_completed(futures):
                results.append(f.result())
                bar.advance(results[-1])
    finally:
        bar.clear()
    return Batch.of_plan(planned, results, start)
