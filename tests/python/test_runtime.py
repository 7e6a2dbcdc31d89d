"""The package around the computation: the GIL released, memory not
growing, the library found and checked."""

import os
import re
import subprocess
import sys
import threading
import time

import numpy as np
import pytest

import vn
from conftest import SANITIZED, SOURCE, grid

PYTHON_DIR = os.path.join(SOURCE, "python")


@pytest.fixture(scope="module")
def million():
    p, f = grid(708)  # 1,000,000 triangles
    assert len(f) == 2 * 707 * 707
    return p, f.astype(np.uint32)


def run_watched(jobs):
    """Runs each job on its own thread while this thread keeps running
    Python; returns (the longest pause of this thread, every job call's
    duration). Pauses are measured with a 0.5 ms switch interval."""
    durations, ticks = [], []

    def timed(job):
        for _ in range(3):
            t0 = time.perf_counter()
            job()
            durations.append(time.perf_counter() - t0)

    threads = [threading.Thread(target=timed, args=(job,)) for job in jobs]
    interval = sys.getswitchinterval()
    sys.setswitchinterval(0.0005)
    try:
        for t in threads:
            t.start()
        while any(t.is_alive() for t in threads):
            ticks.append(time.perf_counter())
    finally:
        sys.setswitchinterval(interval)
    return np.diff(ticks).max(), durations


def test_gil_released_while_computing(million):
    """This thread keeps running Python while a worker thread computes the
    corner normals of a 1M-triangle mesh: its longest pause is far below
    one computation. Holding the GIL would stop it for each whole call
    (then the pause is most of a call), however many cores there are;
    a busy machine pauses it for a few time slices at most."""
    p, f = million
    pause, durations = run_watched([lambda: vn.corner_normals(p, f, crease_angle=0.5, threads=1)])
    assert min(durations) > 0.05, durations
    assert pause < 0.4 * min(durations), (pause, durations)


def test_two_threads_compute_at_once(million):
    """Two threads computing at once, and this one still runs Python between
    their calls' starts and ends: neither holds the GIL while computing."""
    p, f = million
    job = lambda: vn.corner_normals(p, f, "mwaat", crease_angle=0.5, threads=1)  # noqa: E731
    pause, durations = run_watched([job, job])
    assert len(durations) == 6 and min(durations) > 0.05, durations
    assert pause < 0.4 * min(durations), (pause, durations)


@pytest.mark.skipif(SANITIZED, reason="AddressSanitizer keeps freed memory in quarantine")
def test_repeated_calls_do_not_grow_rss():
    p, f = grid(300, jitter=0.001)  # 90000 vertices: 2.1 MB of normals a call

    def rss():
        with open("/proc/self/statm") as s:
            return int(s.read().split()[1]) * os.sysconf("SC_PAGE_SIZE")

    def calls():
        for method in ("mwa", "mwselr"):
            vn.vertex_normals(p, f, method)
            vn.vertex_normals(p.astype(np.float32), f.astype(np.int64), method, threads=2)
            vn.corner_normals(p, f, method, crease_angle=0.3)
        vn.weld(p)
        try:
            vn.vertex_normals(p, f + len(p))
        except vn.Error:
            pass

    for _ in range(5):
        calls()
    before = rss()
    for _ in range(60):
        calls()
    grown = rss() - before
    # 60 rounds allocate about 1.4 GB; a leak of one output a call would show as hundreds of MB
    assert grown < 16 << 20, grown


def run_python(code, **env):
    e = {k: v for k, v in os.environ.items() if k != "VN_LIBRARY"}
    e.update(env)
    return subprocess.run([sys.executable, "-c", code], env=e, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                          universal_newlines=True)


def test_vn_library_override_errors():
    code = "import vn\ntry:\n    vn.methods()\nexcept vn.Error as e:\n    print(e)\n"
    r = run_python(code, VN_LIBRARY="/nonexistent/libvn.so", PYTHONPATH=PYTHON_DIR)
    assert r.stdout.strip() == ("cannot load the vn library: /nonexistent/libvn.so does not exist "
                                "(library path from the VN_LIBRARY environment variable)"), r.stderr
    r = run_python(code, VN_LIBRARY=sys.executable, PYTHONPATH=PYTHON_DIR)
    assert r.stdout.strip() == ("%s is not a vn library: it does not export vn_version (library path from the "
                                "VN_LIBRARY environment variable)" % os.path.abspath(sys.executable)), r.stderr


def test_source_tree_library_found():
    build = os.path.join(SOURCE, "build", "libvn.so")
    if not os.path.exists(build):
        pytest.skip("no build/libvn.so in the source tree")
    r = run_python("import vn; print(vn.library().path)", PYTHONPATH=PYTHON_DIR)
    assert os.path.realpath(r.stdout.strip()) == os.path.realpath(build), r.stderr


def test_binding_version_is_vn_h():
    with open(os.path.join(SOURCE, "src", "vn.h")) as h:
        version = re.search(r'#define VN_VERSION_STRING "([^"]+)"', h.read()).group(1)
    assert vn.__version__ == version == vn.library().version
