"""vn.dask on a real Dask cluster (Debian's python3-distributed): a
LocalCluster of 2 worker processes on the loopback address. The outputs
against vnconvert --out-dir's byte for byte, failures per file, reruns
that skip what is done, and a worker killed mid-run."""

import os
import signal
import subprocess
import sys
import threading
import time

import pytest

import vn
from conftest import batch_lines, grid, native, same_trees, write_off

distributed = pytest.importorskip("distributed")
import vn.dask  # noqa: E402

VNCONVERT = os.environ.get("VNCONVERT")
needs_vnconvert = pytest.mark.skipif(not VNCONVERT, reason="VNCONVERT: the build has no tools (VN_BUILD_TOOLS=OFF)")


@pytest.fixture(scope="module")
def client():
    cluster = distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, host="127.0.0.1",
                                       dashboard_address=":0", silence_logs=50)
    with distributed.Client(cluster) as c:
        yield c
    cluster.close()


def vnconvert_batch(out, *args):
    p = native([VNCONVERT, "--out-dir", out] + list(args), stderr=subprocess.PIPE, universal_newlines=True)
    return p.returncode, p.stderr


@needs_vnconvert
def test_outputs_are_vnconvert_s(tmp_path, models, client):
    b = vn.dask.convert_many(client, [models], tmp_path / "dask", "mwselr", recursive=True, format="glb",
                             crease_angle=25)
    status, err = vnconvert_batch(tmp_path / "c", "-r", models, "-f", "glb", "-m", "mwselr", "--crease-angle", "25")
    assert status == 1
    same_trees(tmp_path / "dask", tmp_path / "c")
    fails, summary = batch_lines(err)
    assert {f.input: f.message for f in b.failed} == fails
    assert sorted(fails) == [str(models / n) for n in ("bad.off", "nan.off", "wild/gltf1.gltf", "wild/no-data.gltf")]
    assert summary.startswith("vnconvert: %d files converted, 4 failed, 6 skipped (not a format vn reads); %s "
                              "triangles in" % (len(b.converted), format(b.triangles, ",")))
    assert len(b.converted) == 20
    workers = set(client.nthreads())
    assert {f.worker for f in b.converted} <= workers and all(f.worker for f in b.converted)
    assert b.input_bytes == sum(os.path.getsize(f.input) for f in b.converted)


def test_rerun_skips_what_is_done(tmp_path, models, client):
    out = tmp_path / "out"
    first = vn.dask.convert_many(client, models / "fields", out, format="drc", draco_qp=16)
    assert [f.status for f in first.files] == ["converted"] * 4
    stamps = {f.output: os.stat(f.output).st_mtime_ns for f in first.files}
    os.remove(first.files[3].output)
    again = vn.dask.convert_many(client, models / "fields", out, format="drc", draco_qp=16)
    assert [f.status for f in again.files] == ["done"] * 3 + ["converted"]
    assert all(os.stat(f.output).st_mtime_ns == stamps[f.output] for f in again.files[:3])
    assert again.summary().startswith("1 file converted, 3 done before (skipped); ")
    forced = vn.dask.convert_many(client, models / "fields", out, format="drc", draco_qp=16, overwrite=True)
    assert [f.status for f in forced.files] == ["converted"] * 4


def test_refused_before_any_task(tmp_path, models, client):
    with pytest.raises(vn.Error, match="^--draco-qp needs a whole number of bits from 1 to 30, not '0'$"):
        vn.dask.convert_many(client, models / "fields", tmp_path / "out", draco_qp=0)
    with pytest.raises(vn.Error, match="would both be written to"):
        vn.dask.convert_many(client, [models / "torus.off", models / "torus.off"], tmp_path / "out")
    assert not (tmp_path / "out").exists()


@needs_vnconvert
def test_killed_worker_loses_nothing(tmp_path, client):
    """The worker converting the first (largest) file is killed (SIGKILL)
    while it works: the task runs again on a worker, every output is
    vnconvert's and no temporary file is left."""
    folder = tmp_path / "in"
    os.mkdir(folder)
    write_off(folder / "a_large.off", *grid(500, jitter=1e-4))  # ~500k triangles: converting takes a while
    for k in range(6):
        write_off(folder / ("b%d.off" % k), *grid(30 + k, jitter=0.002, seed=k))
    pids = client.run(os.getpid)
    result = {}
    run = threading.Thread(target=lambda: result.update(
        b=vn.dask.convert_many(client, folder, tmp_path / "dask", format="obj", progress=False)))
    run.start()
    deadline, victim = time.monotonic() + 60, None
    while victim is None and time.monotonic() < deadline:
        for worker, keys in client.processing().items():
            if any(str(k).endswith("-0") for k in keys):
                victim = worker
        time.sleep(0.01)
    assert victim, "the first file's task was never seen on a worker"
    time.sleep(0.3)  # into the conversion (reading alone takes longer)
    os.kill(pids[victim], signal.SIGKILL)
    run.join(timeout=300)
    assert not run.is_alive()
    b = result["b"]
    assert [f.status for f in b.files] == ["converted"] * 7
    assert b.files[0].worker != victim
    status, _ = vnconvert_batch(tmp_path / "c", folder, "-f", "obj")
    assert status == 0
    names = same_trees(tmp_path / "dask", tmp_path / "c")
    assert names == ["a_large.obj"] + ["b%d.obj" % k for k in range(6)]  # no temporaries


@needs_vnconvert
def test_command_line(tmp_path, models, client):
    """python3 -m vn.dask against the running scheduler: vnconvert's flags,
    FAIL lines, the summary, exit status 1 for a failed file."""
    env = dict(os.environ)
    argv = [sys.executable, "-m", "vn.dask", "--scheduler", client.scheduler.address, "-o", tmp_path / "dask", "-r",
            models / "wild", models / "fields", "-m", "mwaat", "-f", "glb", "--no-weld"]
    p = subprocess.run([str(a) for a in argv], stderr=subprocess.PIPE, universal_newlines=True, env=env)
    assert p.returncode == 1, p.stderr
    status, err = vnconvert_batch(tmp_path / "c", "-r", models / "wild", models / "fields", "-m", "mwaat", "-f", "glb",
                                  "--no-weld")
    assert status == 1
    same_trees(tmp_path / "dask", tmp_path / "c")
    lines = p.stderr.splitlines()
    assert sorted(line for line in lines if line.startswith("FAIL ")) == sorted(
        line for line in err.splitlines() if line.startswith("FAIL "))
    _, summary = batch_lines(err)
    counts = summary[len("vnconvert: "):summary.index(" triangles in ")]
    assert lines[-1].startswith("vn.dask: %s triangles, " % counts)
    assert counts.startswith("12 files converted, 2 failed, 4 skipped")
    assert lines[-1].endswith(" on 2 workers") or lines[-1].endswith(" on 1 workers")
    rerun = subprocess.run([str(a) for a in argv], stderr=subprocess.PIPE, universal_newlines=True, env=env)
    assert rerun.returncode == 1  # the two that fail fail again; the rest is done
    assert "0 files converted, 2 failed, 12 done before (skipped)" in rerun.stderr.splitlines()[-1]


@pytest.mark.parametrize("argv, message", [
    (["--local", "1", "-o", "x"], "the following arguments are required: INPUT"),
    (["-o", "x", "in.off"], "one of the arguments --scheduler --local is required"),
    (["--local", "1", "-o", "x", "in.off", "--draco-qp"], "vn.dask: error: option --draco-qp needs a value"),
    (["--local", "1", "-o", "x", "in.xyz"], "vn.dask: error: cannot tell the format of 'in.xyz' from its extension"),
])
def test_usage_errors(tmp_path, argv, message):
    p = subprocess.run([sys.executable, "-m", "vn.dask"] + argv, stderr=subprocess.PIPE, universal_newlines=True,
                       cwd=tmp_path)
    assert p.returncode == 2
    assert message in p.stderr
    assert os.listdir(tmp_path) == []


def test_help():
    p = subprocess.run([sys.executable, "-m", "vn.dask", "--help"], stdout=subprocess.PIPE, universal_newlines=True)
    assert p.returncode == 0
    assert "--scheduler ADDRESS" in p.stdout and "--crease-angle" in p.stdout


def test_close_timeout_noise_dropped(caplog):
    """The message an unread TimeoutError leaves when distributed's client
    closes is dropped (it ended a run that went well, after its summary:
    test_command_line then saw it as the last line); any other unread
    exception is still reported."""
    import asyncio
    import gc
    loop = asyncio.new_event_loop()
    vn.dask._quiet_close(loop)
    with caplog.at_level("ERROR", logger="asyncio"):
        for exception in (TimeoutError("Timeout"), ValueError("kept")):
            f = loop.create_future()
            f.set_exception(exception)
            del f
            gc.collect()
    loop.close()
    messages = [r.getMessage() for r in caplog.records if r.name == "asyncio"]
    assert len(messages) == 1 and "Future exception was never retrieved" in messages[0]
    assert "ValueError" in caplog.text and "Timeout" not in caplog.text
