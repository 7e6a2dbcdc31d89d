"""vn.convert against vnconvert: the same bytes, warnings and messages (both
call vn_io_convert), and the ctypes structs against vn_convert.h."""

import os
import pathlib
import subprocess
import threading

import pytest

import vn
from vn import _convert
from conftest import SOURCE, batch_lines, native, same_trees

VNCONVERT = os.environ.get("VNCONVERT")
needs_vnconvert = pytest.mark.skipif(not VNCONVERT, reason="VNCONVERT: the build has no tools (VN_BUILD_TOOLS=OFF)")
TORUS = os.path.join(SOURCE, "samples", "torus.off")
SPHERE_OBJ = os.path.join(SOURCE, "tests", "data", "obj", "blender_sphere.obj")
ISOLATED = "OFF\n8 1 0\n0 0 0\n1 0 0\n0 1 0\n5 5 5\n6 6 6\n7 7 7\n8 8 8\n9 9 9\n3 0 1 2\n"


def vnconvert(*args):
    """(exit status, stdout, stderr) of build/vnconvert, run without the
    sanitizer runtime preloaded for python (it carries its own)."""
    p = native([VNCONVERT] + list(args), stderr=subprocess.PIPE, universal_newlines=True)
    return p.returncode, p.stdout, p.stderr


def vnconvert_lines(stderr, kind):
    prefix = "vnconvert: %s: " % kind
    return [line[len(prefix):] for line in stderr.splitlines() if line.startswith(prefix)]


def test_struct_layout():
    """Every field of the ctypes copies at the C compiler's offset, and the
    same sizes: fails when vn_convert.h changes and _convert.py does not."""
    out = native([os.environ["VN_CONVERT_LAYOUT"]], check=True, universal_newlines=True).stdout
    c = {}
    for line in out.splitlines():
        struct, field, value = line.split()
        c.setdefault(struct, {})[field] = int(value)
    for struct, cls in (("vn_convert_options", _convert._ConvertOptions),
                        ("vn_convert_report", _convert._ConvertReport), ("vn_batch_file", _convert._BatchFile),
                        ("vn_batch_plan", _convert._BatchPlan)):
        py = {name: getattr(cls, name).offset for name, _ in cls._fields_}
        py["sizeof"] = __import__("ctypes").sizeof(cls)
        assert py == c[struct]


def test_options_set_through_the_library():
    """Each keyword lands in the field vn_io_convert_option sets, read back
    through the ctypes struct."""
    io = _convert.io_library(vn.library().path)
    o = io.options("MWSELR", dict(input_format="off", format="glb", threads=3, in_place=True, no_weld=True,
                                  weld_epsilon=0.25, crease_angle=30, weld_scope="mesh", tangents="drop",
                                  draco="on", meshopt="off", draco_qp=11, draco_qn=9, draco_qt=8, draco_qc=7,
                                  draco_cl=4, apply_transforms=True, stats=True))
    got = {name: getattr(o, name) for name, _ in o._fields_}
    assert got == dict(input_format=b"off", output_format=b"glb", method=b"mwselr", threads=3, in_place=1,
                       no_weld=1, weld_epsilon=0.25, crease=1, crease_angle=30.0, weld_scope=b"mesh",
                       tangents=b"drop", draco=b"on", meshopt=b"off", draco_qp=11, draco_qn=9, draco_qt=8,
                       draco_qc=7, draco_cl_set=1, draco_cl=4, apply_transforms=1, stats=1, ignore_misfits=0,
                       image_names_from_output=0, input_is_copy=0, progress=None, progress_context=None)
    off = io.options("mwa", dict(no_weld=False, crease_angle=None))
    assert (off.no_weld, off.crease, off.method) == (0, 0, b"mwa")


CASES = [
    (TORUS, "glb", "mwa", {}, []),
    (TORUS, "glb", "mwselr", dict(crease_angle=30), ["--crease-angle", "30"]),
    (TORUS, "glb", "mwaat", dict(no_weld=True, threads=1), ["--no-weld", "-j", "1"]),
    (TORUS, "drc", "mwe", dict(draco_qp=11, draco_qn=8, draco_cl=4), ["--draco-qp", "11", "--draco-qn", "8",
                                                                      "--draco-cl", "4"]),
    (TORUS, "bin", "mwa", dict(format="glb", weld_epsilon=1e-3), ["--format", "glb", "--weld-epsilon", "0.001"]),
    (SPHERE_OBJ, "ply", "mwa", {}, []),
    (SPHERE_OBJ, "ply", "mwrelr", dict(crease_angle=12.5, weld_epsilon=1e-6),
     ["--crease-angle", "12.5", "--weld-epsilon", "1e-06"]),
    (SPHERE_OBJ, "obj", "mewcsa", dict(no_weld=True), ["--no-weld"]),
]


@needs_vnconvert
@pytest.mark.parametrize("src, ext, method, options, flags", CASES)
def test_same_bytes_as_vnconvert(tmp_path, src, ext, method, options, flags):
    ours, theirs = tmp_path / ("py." + ext), tmp_path / ("c." + ext)
    r = vn.convert(src, ours, method, **options)
    status, _, err = vnconvert(src, theirs, "-m", method, *flags)
    assert status == 0
    assert ours.read_bytes() == theirs.read_bytes()
    assert r.warnings == [w.replace(str(theirs), str(ours)) for w in vnconvert_lines(err, "warning")]
    assert (r.method, r.output_format) == (method, options.get("format", ext))
    assert r.input_format == os.path.splitext(src)[1][1:]


@needs_vnconvert
def test_report_matches_stats(tmp_path):
    """The counts and formats as vnconvert --stats prints them."""
    r = vn.convert(TORUS, tmp_path / "t.drc", "mwselr", crease_angle=10, draco_qp=11, stats=True)
    _, stats, _ = vnconvert(TORUS, tmp_path / "c.drc", "-m", "mwselr", "--crease-angle", "10", "--draco-qp", "11",
                            "--stats")
    fields = dict(line.split(":", 1) for line in stats.splitlines() if ":" in line)
    fields = {k: v.strip() for k, v in fields.items()}
    assert (r.vertices, r.faces, r.triangles) == (960, 1920, 1920)
    assert "%d (triangles)" % r.faces == fields["faces"]
    for name, key in (("vertices", "vertices"), ("degenerate_faces", "degenerate faces"),
                      ("welded_vertices", "welded vertices"), ("hard_edges", "hard edges kept"),
                      ("split_vertices", "split vertices"), ("zero_normals", "zero normals")):
        assert str(getattr(r, name)) == fields[key], name
    assert r.split_vertices == 1026
    assert fields["method"] == r.method == "mwselr"
    assert fields["draco normal quantization error"].endswith("(qn=10, %d normals)" % r.draco_normals_compared)
    assert (r.draco_normal_bits, r.draco_normals_compared) == (10, r.vertices + r.split_vertices)
    assert 0 < r.draco_normal_median_degrees <= r.draco_normal_max_degrees < 1
    assert 0 < r.read_seconds + r.normals_seconds + r.write_seconds <= r.seconds
    assert r.stats.splitlines()[2:5] == stats.splitlines()[2:5]  # method, vertices, faces (paths differ)


@needs_vnconvert
@pytest.mark.parametrize("ext", ["drc", "glb", "obj", "ply", "stl"])
def test_warnings(tmp_path, ext):
    """An isolated vertex: vnconvert's warnings, as a list."""
    src = tmp_path / "isolated.off"
    src.write_text(ISOLATED)
    r = vn.convert(src, tmp_path / ("py." + ext))
    status, _, err = vnconvert(src, tmp_path / ("py." + ext), "--in-place")
    assert status == 0
    assert r.warnings == vnconvert_lines(err, "warning")
    assert len(r.warnings) == (2 if ext in ("drc", "stl") else 1)
    assert r.zero_normals == 5


ERRORS = [
    ("missing.off", "out.glb", {}, ["missing.off", "out.glb"]),
    (TORUS, "out.glb", dict(draco_qp=31), [TORUS, "out.glb", "--draco-qp", "31"]),
    (TORUS, "out.glb", dict(crease_angle=-1), [TORUS, "out.glb", "--crease-angle", "-1"]),
    (TORUS, "out.glb", dict(weld_scope="all"), [TORUS, "out.glb", "--weld-scope", "all"]),
    (TORUS, "out.glb", dict(threads=0), [TORUS, "out.glb", "--threads", "0"]),
    (TORUS, "out.obj", dict(draco_qp=11), [TORUS, "out.obj", "--draco-qp", "11"]),  # misfit
    (TORUS, "out.obj", dict(tangents="drop"), [TORUS, "out.obj", "--tangents", "drop"]),  # misfit
    (TORUS, "out.xyz", {}, [TORUS, "out.xyz"]),
    (TORUS, "out.glb", dict(input_format="stl"), [TORUS, "out.glb", "--input-format", "stl"]),
]


@needs_vnconvert
@pytest.mark.parametrize("src, dst, options, argv", ERRORS)
def test_errors_are_vnconverts(tmp_path, monkeypatch, src, dst, options, argv):
    """The one-line message vnconvert prints after "error: ", and no output."""
    monkeypatch.chdir(tmp_path)
    status, _, err = vnconvert(*argv)
    assert status != 0 and not os.path.exists(dst)
    with pytest.raises(vn.Error) as e:
        vn.convert(src, dst, **options)
    assert [str(e.value)] == vnconvert_lines(err, "error")
    assert sorted(os.listdir(tmp_path)) == []


def test_method_given_as_an_entry_of_methods(tmp_path):
    mwselr = [m for m in vn.methods() if m.name == "mwselr"][0]
    vn.convert(TORUS, tmp_path / "a.off", mwselr)
    vn.convert(TORUS, tmp_path / "b.off", "mwselr")
    assert (tmp_path / "a.off").read_bytes() == (tmp_path / "b.off").read_bytes()


def test_bad_method(tmp_path):
    with pytest.raises(vn.Error, match=r"^--method is one of mwe, mwa, .*, not 'zz' \(see --list-methods\)$"):
        vn.convert(TORUS, tmp_path / "t.glb", "zz")
    assert os.listdir(tmp_path) == []


@pytest.mark.parametrize("options, message", [
    (dict(crease=30), "convert() has no option crease (vnconvert has no --crease)"),
    (dict(out_dir="x"), "give dst (one file) or out_dir (a batch), not both"),
    (dict(recursive=True), "recursive, overwrite and progress are for a batch: give out_dir"),
    (dict(out="x"), "convert() has no option out (vnconvert has no --out)"),
    ({"crease-angle": 30}, "convert() has no option crease-angle (vnconvert has no --crease-angle)"),
    (dict(no_weld=1), "option no_weld is a switch: True or False, not 1"),
])
def test_keyword_errors(tmp_path, options, message):
    with pytest.raises(vn.Error) as e:
        vn.convert(TORUS, tmp_path / "t.glb", **options)
    assert str(e.value) == message
    assert os.listdir(tmp_path) == []


def test_failure_leaves_output_as_it_was(tmp_path):
    dst = tmp_path / "t.glb"
    dst.write_bytes(b"before")
    bad = tmp_path / "bad.off"
    bad.write_text("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n")
    with pytest.raises(vn.Error, match="^%s:" % bad):
        vn.convert(bad, dst)
    assert dst.read_bytes() == b"before"
    assert sorted(os.listdir(tmp_path)) == ["bad.off", "t.glb"]  # no temporary left


def test_same_file_needs_in_place(tmp_path):
    src = tmp_path / "t.off"
    src.write_bytes(pathlib.Path(TORUS).read_bytes())
    with pytest.raises(vn.Error, match="in-place"):
        vn.convert(src, src)
    assert src.read_bytes() == pathlib.Path(TORUS).read_bytes()
    r = vn.convert(src, src, in_place=True)
    assert r.triangles == 1920 and src.read_bytes() != pathlib.Path(TORUS).read_bytes()


def test_threads_convert_side_by_side(tmp_path):
    """No shared state: 8 conversions on 4 Python threads, each with its own
    options, give what one conversion alone gives."""
    methods = [m.name for m in vn.methods()] + ["mwa"]
    crease = [10 * methods.index(m) for m in methods]
    alone = {}
    for i, m in enumerate(methods):
        vn.convert(TORUS, tmp_path / ("alone%d.glb" % i), m, crease_angle=crease[i])
        alone[i] = (tmp_path / ("alone%d.glb" % i)).read_bytes()
    errors = []

    def work(indices):
        try:
            for i in indices:
                vn.convert(TORUS, tmp_path / ("thread%d.glb" % i), methods[i], crease_angle=crease[i], threads=1)
        except Exception as e:  # reported below, with the thread's index
            errors.append(e)

    threads = [threading.Thread(target=work, args=(range(k, len(methods), 4),)) for k in range(4)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert errors == []
    for i in alone:
        assert (tmp_path / ("thread%d.glb" % i)).read_bytes() == alone[i], methods[i]
    # the seven all differ (beyond them, ADAPTIVE is JET on this smooth torus)
    assert len({alone[i] for i in range(7)}) == 7


def test_libvnio_from_env(monkeypatch):
    monkeypatch.setenv("VN_LIBVNIO", "/nonexistent/libvnio.so")
    with pytest.raises(vn.Error, match=r"^cannot load the vn I/O library: /nonexistent/libvnio.so does not exist "
                                       r"\(library path from the VN_LIBVNIO environment variable\)$"):
        vn.convert(TORUS, "unused.glb")
    monkeypatch.setenv("VN_LIBVNIO", vn.library().path)
    with pytest.raises(vn.Error, match="is not vn's I/O library: it does not export vn_io_convert"):
        vn.convert(TORUS, "unused.glb")


# ------------------------------------------------------------------ batches


@needs_vnconvert
@pytest.mark.parametrize("options, flags, failing", [
    ({}, [], ["bad.off", "nan.off", "wild/gltf1.gltf"]),
    # A .gltf whose buffer has no data can stay .gltf, but not become .glb.
    (dict(format="glb", method="mwselr", crease_angle=30), ["-f", "glb", "-m", "mwselr", "--crease-angle", "30"],
     ["bad.off", "nan.off", "wild/gltf1.gltf", "wild/no-data.gltf"])])
def test_batch_is_vnconvert_s(tmp_path, models, options, flags, failing):
    """vn.convert(out_dir=...) and vnconvert --out-dir on one folder: the
    same files, byte for byte, the same failures with the same messages,
    and the counts of vnconvert's summary."""
    options = dict(options)
    b = vn.convert([models], out_dir=tmp_path / "py", recursive=True, threads=2, **options)
    status, _, err = vnconvert("--out-dir", tmp_path / "c", "-r", models, "-j", "2", *flags)
    assert status == 1  # some files fail
    names = same_trees(tmp_path / "py", tmp_path / "c")
    fails, summary = batch_lines(err)
    assert {f.input: f.message for f in b.failed} == fails
    assert sorted(fails) == [str(models / n) for n in failing]
    assert summary.startswith("vnconvert: %d files converted, %d failed, %d skipped (not a format vn reads); %s "
                              "triangles in " % (len(b.converted), len(failing), b.skipped,
                                                 format(b.triangles, ",")))
    assert len(b.converted) + len(failing) == 24 and b.skipped == 6 and b.unentered == 0
    assert [f.input for f in b.files] == sorted(f.input for f in b.files)  # the plan's order: names
    assert all(f.output_bytes == os.path.getsize(f.output) for f in b.converted)
    assert {f.input: f.triangles for f in b.converted}[str(models / "torus.off")] == 1920
    assert len(names) > len(b.converted)  # images copied beside .gltf outputs
    assert b.triangles == sum(f.triangles for f in b.converted)


def test_batch_resumes(tmp_path, models):
    """overwrite=False: outputs there and not older than their inputs are
    left alone; a missing output, or one older than its input, is made
    again."""
    import shutil
    fields, out = tmp_path / "fields", tmp_path / "out"
    shutil.copytree(models / "fields", fields)
    first = vn.convert(fields, out_dir=out, format="ply")
    assert [f.status for f in first.files] == ["converted"] * 4
    stamps = {f.output: os.stat(f.output).st_mtime_ns for f in first.files}
    again = vn.convert(fields, out_dir=out, format="ply", overwrite=False)
    assert [f.status for f in again.files] == ["done"] * 4
    assert {f.output: os.stat(f.output).st_mtime_ns for f in again.files} == stamps
    os.remove(first.files[1].output)
    newer = stamps[first.files[2].output] + 10 ** 9
    os.utime(first.files[2].input, ns=(newer, newer))
    third = vn.convert(fields, out_dir=out, format="ply", overwrite=False)
    assert [f.status for f in third.files] == ["done", "converted", "converted", "done"]
    assert os.stat(first.files[0].output).st_mtime_ns == stamps[first.files[0].output]


def test_batch_refused_before_any_work(tmp_path, models):
    out = tmp_path / "out"
    with pytest.raises(vn.Error) as e:
        vn.convert([models / "torus.off", models / "fields", models / "torus.off"], out_dir=out)
    assert str(e.value) == "'%s' and '%s' would both be written to '%s': convert them into different folders" % (
        models / "torus.off", models / "torus.off", out / "torus.off")
    with pytest.raises(vn.Error, match="^--tangents applies only to glTF to glTF .*no file of this batch"):
        vn.convert(models / "fields", out_dir=out, tangents="drop")
    with pytest.raises(vn.Error, match="^stats is for one file"):
        vn.convert(models / "fields", out_dir=out, stats=True)
    assert not out.exists()


def test_batch_progress_callback(tmp_path, models):
    seen = []
    b = vn.convert(models / "fields", out_dir=tmp_path, progress=lambda *a: seen.append(a))
    assert sorted((done, total) for done, total, _ in seen) == [(1, 4), (2, 4), (3, 4), (4, 4)]
    assert sorted(r.output for _, _, r in seen) == [f.output for f in b.files]
