"""Shared by the vn package's tests: the meshes and vn_raw, the C side."""

import os
import subprocess
import tempfile

import numpy as np
import pytest

SOURCE = os.environ.get("VN_SOURCE_DIR", os.path.join(os.path.dirname(__file__), os.pardir, os.pardir))
SANITIZED = bool(os.environ.get("VN_SANITIZED"))


def read_off(path):
    """(positions float64 (n, 3), faces: (m, 3) when all are triangles, else
    (indices, offsets)) of an OFF file, parsed as strtod does (correctly rounded)."""
    with open(path) as f:
        words = [w for line in f for w in line.split("#")[0].split()]
    assert words[0] == "OFF"
    n, m = int(words[1]), int(words[2])
    p = np.array(words[4:4 + 3 * n], dtype=np.float64).reshape(n, 3)
    rest, faces = words[4 + 3 * n:], []
    for _ in range(m):
        k = int(rest[0])
        faces.append([int(w) for w in rest[1:1 + k]])
        rest = rest[1 + k:]
    if all(len(f) == 3 for f in faces):
        return p, np.array(faces)
    return p, (np.concatenate(faces), np.cumsum([0] + [len(f) for f in faces]))


@pytest.fixture(scope="session")
def torus():
    return read_off(os.path.join(SOURCE, "samples", "torus.off"))


@pytest.fixture(scope="session")
def sphere_quads():
    return read_off(os.path.join(SOURCE, "samples", "sphere-quads.off"))


def grid(k, jitter=0.0, seed=1):
    """A k x k vertex height field: 2 (k - 1)^2 triangles, rows of faces
    int64, z bumpy so that the methods differ."""
    x, y = np.meshgrid(np.linspace(0, 1, k), np.linspace(0, 1, k), indexing="ij")
    z = 0.1 * np.sin(7 * x) * np.cos(5 * y)
    p = np.stack([x, y, z], axis=-1).reshape(-1, 3)
    if jitter:
        p += np.random.default_rng(seed).uniform(-jitter, jitter, p.shape)
    v = np.arange(k * k).reshape(k, k)
    a, b, c, d = v[:-1, :-1].ravel(), v[1:, :-1].ravel(), v[1:, 1:].ravel(), v[:-1, 1:].ravel()
    return p, np.concatenate([np.stack([a, b, c], 1), np.stack([a, c, d], 1)])


def native(args, **kwargs):
    """subprocess.run of one of the build's programs, without the sanitizer
    runtime preloaded for python: an ASan build's programs carry their own,
    and two runtimes in one process abort."""
    env = {k: v for k, v in os.environ.items() if k != "LD_PRELOAD"}
    return subprocess.run([str(a) for a in args], stdout=subprocess.PIPE, env=env, **kwargs)


def c_normals(kind, method, positions, faces, crease=None):
    """vn_raw's normals (float64 rows): the same library called from C."""
    raw = os.environ["VN_RAW"]
    with tempfile.TemporaryDirectory() as d:
        files = [os.path.join(d, "p"), os.path.join(d, "i")]
        np.ascontiguousarray(positions, dtype=np.float64).tofile(files[0])
        if isinstance(faces, tuple):
            np.asarray(faces[0], dtype=np.uint32).tofile(files[1])
            files.append(os.path.join(d, "o"))
            np.asarray(faces[1], dtype=np.uint32).tofile(files[2])
        else:
            np.asarray(faces, dtype=np.uint32).tofile(files[1])
        args = [raw, kind, method] + files + ([] if crease is None else [repr(float(crease))])
        out = native(args, check=True).stdout
    return np.frombuffer(out, dtype=np.float64).reshape(-1, 3)


def write_off(path, positions, faces):
    """An OFF file of the mesh (repr of each float: read back exactly)."""
    with open(path, "w") as f:
        f.write("OFF\n%d %d 0\n" % (len(positions), len(faces)))
        f.write("\n".join("%r %r %r" % tuple(p) for p in positions.tolist()))
        f.write("\n" + "\n".join("3 %d %d %d" % tuple(t) for t in faces.tolist()) + "\n")


@pytest.fixture(scope="session")
def models(tmp_path_factory):
    """A folder of models as a batch meets them: every format vn reads, from
    the samples and test data (Blender, Draco and glTF files with images),
    generated height fields in a subfolder, files that fail (malformed, a
    NaN position, glTF 1.0) and files of no format vn reads."""
    import shutil
    root = tmp_path_factory.mktemp("models")
    data = os.path.join(SOURCE, "tests", "data")
    for src in [os.path.join(SOURCE, "samples", "torus.off"), os.path.join(SOURCE, "samples", "sphere-quads.off"),
                os.path.join(data, "gltf", "shapes.glb"), os.path.join(data, "gltf", "quantized.glb"),
                os.path.join(data, "draco", "colored.drc"), os.path.join(data, "obj", "blender_cube.obj"),
                os.path.join(data, "obj", "blender_cube.mtl"), os.path.join(data, "ply", "blender_binary.ply"),
                os.path.join(data, "stl", "test_sphere.stl"), os.path.join(data, "obj", "README.md")]:
        shutil.copy(src, root)
    shutil.copytree(os.path.join(data, "gltf", "wild"), root / "wild")
    os.mkdir(root / "fields")
    for k in range(4):
        write_off(root / "fields" / ("field%d.off" % k), *grid(40 + 10 * k, jitter=0.002, seed=k))
    (root / "bad.off").write_text("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n")
    (root / "nan.off").write_text("OFF\n3 1 0\n0 0 0\nnan 0 0\n0 1 0\n3 0 1 2\n")
    return root


def same_trees(a, b):
    """The relative paths of the files under a, after checking b holds the
    same files with the same bytes."""
    def files(root):
        return sorted(os.path.relpath(os.path.join(d, n), root) for d, _, names in os.walk(root) for n in names)
    fa = files(a)
    assert fa == files(b)
    for f in fa:
        with open(os.path.join(a, f), "rb") as x, open(os.path.join(b, f), "rb") as y:
            assert x.read() == y.read(), f
    return fa


def batch_lines(stderr):
    """{input: message} of vnconvert --out-dir's FAIL lines, and its summary line."""
    fails = dict(line[5:].split(": ", 1) for line in stderr.splitlines() if line.startswith("FAIL "))
    summary = [line for line in stderr.splitlines() if line.startswith("vnconvert: ") and "converted" in line]
    return fails, summary[-1]
