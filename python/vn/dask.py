"""vn.dask: a batch conversion on a Dask distributed cluster.

The files are planned here as ``vnconvert --out-dir`` plans them
(libvnio's vn_io_batch_plan: the same output names, and the same checks
before any work); each file is then one task that a worker runs with
`vn.convert`'s C code, so the outputs are vnconvert's byte for byte. The
paths must mean the same files on every machine (shared storage).

- One bad file never stops the run: its error comes back in its
  `vn.FileResult`. A file that kills its worker (a crash, or memory) is
  retried on others as Dask retries any task (the scheduler's
  ``allowed-failures``, 3 by default), then reported failed.
- Outputs are written atomically (a temporary file renamed, a .gltf after
  its buffers and images), so a killed worker leaves no partial output, and
  a rerun skips the outputs already there (unless ``overwrite``).
- At most ``window`` tasks are in the cluster at once, so millions of files
  need no more scheduler memory than a few thousand.

Command line::

    python3 -m vn.dask --scheduler tcp://HOST:8786 --out-dir OUT [options] INPUTS...
    python3 -m vn.dask --local 2 --out-dir OUT [options] INPUTS...

Run ``python3 -m vn.dask --help`` for the options.
"""

import argparse
import sys
import time
import uuid

from . import _batch, _convert, library
from ._binding import Error

__all__ = ["convert_many"]


def convert_many(client, inputs, out_dir, method="mwa", *, recursive=False, overwrite=False, progress=None,
                 window=None, **options):
    """Converts files on the cluster `client` is connected to.

    Parameters
    ----------
    client : distributed.Client
    inputs : path or list of paths
        Files, and folders standing for their files of a format vn reads
        (in name order; subfolders with `recursive`).
    out_dir : path
        Each file goes to ``OUT_DIR/STEM.EXT`` as ``vnconvert --out-dir``
        names it. The folders are made here, before the first task.
    method : str, default "mwa"
    recursive : bool, default False
    overwrite : bool, default False
        False skips files whose output exists and is not older than the
        input: a rerun picks up where a stopped one ended.
    progress : None, False or callable
        None: a bar on stderr when it is a terminal; a callable is called
        as ``progress(done, total, file_result)`` as each file ends.
    window : int, optional
        Tasks in the cluster at once; default four per worker thread (at
        least 64).
    **options
        `vn.convert`'s keywords (vnconvert's flags). ``threads`` is each
        conversion's threads (default 1: the workers' threads convert
        files side by side).

    Returns
    -------
    vn.Batch
        A `vn.FileResult` per file, in the plan's order, with the worker
        each ran on; the totals in `vn.Batch.summary`.

    Raises
    ------
    vn.Error
        What refuses the whole batch (before any task): an option's value,
        two inputs for one output, an output that is its input, an input
        whose format is not known, a folder that cannot be made.
    """
    from distributed import as_completed

    start = time.perf_counter()
    io = _convert.io_library(library().path)
    planned = _batch.plan(io, inputs, out_dir, method, recursive, options)
    done, todo = _batch.split(planned[0], overwrite)
    threads = options.get("threads") or 1
    if window is None:
        window = max(64, 4 * sum(client.nthreads().values()))
    token = uuid.uuid4().hex[:8]
    bar = _batch.Progress(progress, len(todo))
    results = list(done)

    def submit(i):
        f = todo[i]
        return client.submit(_task, *f, method, options, threads, key="vnconvert-%s-%d" % (token, i), pure=False)

    first = min(window, len(todo))
    pending = as_completed([submit(i) for i in range(first)], with_results=False)
    following = first
    try:
        for future in pending:
            i = int(future.key.rsplit("-", 1)[1])
            if future.status == "finished":
                r = future.result()
            else:  # a worker died on it allowed-failures times (KilledWorker), or the run was cancelled
                why = _killed(future.exception()) if future.status == "error" else "the task was " + future.status
                r = _batch.FileResult(todo[i][0], todo[i][1], "failed", message="%s: %s" % (todo[i][0], why))
            results.append(r)
            future.release()
            bar.advance(r)
            if following < len(todo):
                pending.add(submit(following))
                following += 1
    finally:
        bar.clear()
    return _batch.Batch.of_plan(planned, results, start)


def _task(*args):
    """One file on a worker: vn.convert's conversion, and where it ran."""
    from distributed import get_worker
    r = _batch.convert_file(*args)
    r.worker = get_worker().address
    return r


def _quiet_close(loop):
    """distributed (Debian's 2022.12) can leave a TimeoutError in a future
    nobody reads while a client closes, and asyncio then prints "Future
    exception was never retrieved ... TimeoutError: Timeout" after the
    summary of a run that went well. That message alone is dropped."""
    def handler(loop, context):
        if not (isinstance(context.get("exception"), TimeoutError)
                and context.get("message", "").startswith("Future exception was never retrieved")):
            loop.default_exception_handler(context)
    loop.set_exception_handler(handler)


def _killed(exception):
    name = type(exception).__name__
    if name == "KilledWorker":
        return ("the workers converting it died (crashed or ran out of memory) as many times as the scheduler "
                "allows (distributed.scheduler.allowed-failures)")
    return "%s: %s" % (name, exception)


def _parser(io):
    p = argparse.ArgumentParser(
        prog="python3 -m vn.dask",
        description="Recomputes the vertex normals of many mesh files on a Dask cluster and writes them into "
                    "one folder, as `vnconvert --out-dir` does (the same output names and bytes). Paths must "
                    "name the same files on every worker (shared storage).",
        epilog="Conversion options are vnconvert's (see vnconvert --help): -m/--method, -f/--format, "
               "--input-format, --no-weld, --weld-epsilon, --crease-angle, --weld-scope, --tangents, --draco, "
               "--meshopt, --draco-qp/qn/qt/qc/cl, --apply-transforms, --in-place; -j/--threads is each "
               "conversion's threads (default 1). Exit status: 0 when every file was converted or done before, "
               "1 when a file failed, 2 when the batch was refused before any work.")
    where = p.add_mutually_exclusive_group(required=True)
    where.add_argument("--scheduler", metavar="ADDRESS", help="the cluster's scheduler (tcp://HOST:8786)")
    where.add_argument("--local", metavar="N", type=int,
                       help="start a cluster of N worker processes on this machine (loopback) instead")
    p.add_argument("-o", "--out-dir", required=True, metavar="DIR", help="where the outputs go")
    p.add_argument("-r", "--recursive", action="store_true", help="enter the subfolders of folder inputs")
    p.add_argument("--overwrite", action="store_true",
                   help="convert every file (default: skip those whose output exists and is not older)")
    p.add_argument("-q", "--quiet", action="store_true", help="only failures: no progress, no summary")
    p.add_argument("-v", "--verbose", action="store_true", help="a line for every file, not only failures")
    p.add_argument("inputs", nargs="+", metavar="INPUT", help="files, and folders of them")
    return p


def main(argv=None):
    """``python3 -m vn.dask``: returns the exit status."""
    argv = sys.argv[1:] if argv is None else list(argv)
    try:
        io = _convert.io_library(library().path)
    except Error as e:
        print("vn.dask: error: %s" % e, file=sys.stderr)
        return 2
    # vnconvert's conversion flags pass through as convert() keywords.
    short = {"-m": "--method", "-f": "--format", "-j": "--threads"}
    options, rest, i = {}, [], 0
    while i < len(argv):
        flag = short.get(argv[i], argv[i])
        arity = io.arity(flag) if flag.startswith("--") else -1
        if arity < 0:
            rest.append(argv[i])
        elif arity == 0:
            options[flag[2:].replace("-", "_")] = True
        elif i + 1 >= len(argv):
            print("vn.dask: error: option %s needs a value" % argv[i], file=sys.stderr)
            return 2
        else:
            i += 1
            options[flag[2:].replace("-", "_")] = argv[i]
        i += 1
    args = _parser(io).parse_args(rest)
    method = options.pop("method", "mwa")
    from distributed import Client, LocalCluster

    cluster = None
    try:
        if args.local is not None:
            if args.local < 1:
                print("vn.dask: error: --local needs at least 1 worker", file=sys.stderr)
                return 2
            cluster = LocalCluster(n_workers=args.local, threads_per_worker=1, host="127.0.0.1",
                                   dashboard_address=":0", silence_logs=40)
        with Client(cluster if cluster is not None else args.scheduler) as client:
            _quiet_close(client.loop.asyncio_loop)
            bar = []  # the terminal's bar, made once the total is known

            def report(done, total, r):
                if not bar:
                    bar.append(_batch.Progress(False if args.quiet else None, total))
                if r.status == "failed" or args.verbose:
                    bar[0].clear()
                    if r.status == "failed":
                        print("FAIL %s: %s" % (r.input, r.message), file=sys.stderr)
                    else:
                        print("ok   %s -> %s  (%s triangles, %.1f ms)" % (r.input, r.output,
                                                                          format(r.triangles, ","),
                                                                          1e3 * r.seconds), file=sys.stderr)
                        for w in r.warnings:
                            print("     warning: %s" % w, file=sys.stderr)
                bar[0].advance(r)

            try:
                batch = convert_many(client, args.inputs, args.out_dir, method, recursive=args.recursive,
                                     overwrite=args.overwrite, progress=report, **options)
            finally:
                if bar:
                    bar[0].clear()
    except Error as e:
        print("vn.dask: error: %s" % e, file=sys.stderr)
        return 2
    finally:
        if cluster is not None:
            cluster.close()
    if not args.quiet:
        workers = len({r.worker for r in batch.converted if r.worker})
        print("vn.dask: %s%s" % (batch.summary(), " on %d workers" % workers if workers else ""), file=sys.stderr)
    return 1 if batch.failed else 0


if __name__ == "__main__":
    sys.exit(main())
