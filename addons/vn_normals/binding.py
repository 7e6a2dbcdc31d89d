"""ctypes binding of vn's shared library (src/vn.h), with numpy arrays.

Pure Python, no bpy: the add-on and its tests both use it. Every function
used is declared with argtypes/restype; a vn_result other than success is
raised as VnError carrying the library's own message (vn_result_string).
"""

import ctypes
import os

import numpy as np

try:
    from . import _build
    # before 1.0 the ABI is the major and minor version's (vn.h, vn_version)
    EXPECTED_ABI = (_build.VN_VERSION_MAJOR, _build.VN_VERSION_MINOR)
except ImportError:  # running from the source tree, not the built package
    EXPECTED_ABI = None

ENV_VAR = "VN_LIBRARY"
BUNDLED = os.path.join(os.path.dirname(os.path.abspath(__file__)), "lib", "libvn.so")


class VnError(Exception):
    """A vn call failed, or the library could not be loaded."""


# vn.h's structs, field for field.
class _Positions(ctypes.Structure):
    _fields_ = [("data", ctypes.c_void_p), ("count", ctypes.c_size_t),
                ("stride", ctypes.c_size_t), ("type", ctypes.c_int)]


class _Vectors(ctypes.Structure):
    _fields_ = [("data", ctypes.c_void_p), ("stride", ctypes.c_size_t), ("type", ctypes.c_int)]


class _Allocator(ctypes.Structure):
    _fields_ = [("allocate", ctypes.c_void_p), ("deallocate", ctypes.c_void_p), ("user", ctypes.c_void_p)]


class _Options(ctypes.Structure):
    _fields_ = [("threads", ctypes.c_uint), ("simd", ctypes.c_int), ("workspace", ctypes.c_void_p),
                ("workspace_size", ctypes.c_size_t), ("allocator", _Allocator), ("face_strength", ctypes.c_void_p),
                ("keep_existing", ctypes.c_int)]


class _Stats(ctypes.Structure):
    _fields_ = [("faces", ctypes.c_size_t), ("degenerate_faces", ctypes.c_size_t),
                ("zero_normals", ctypes.c_size_t), ("nonfinite_vertices", ctypes.c_size_t)]


_FLOAT32, _FLOAT64 = 0, 1
_P = ctypes.POINTER


def _declare(lib):
    c = ctypes
    sigs = {
        "vn_version": (c.c_uint32, []),
        "vn_version_string": (c.c_char_p, []),
        "vn_result_string": (c.c_char_p, [c.c_int]),
        "vn_method_name": (c.c_char_p, [c.c_int]),
        "vn_method_description": (c.c_char_p, [c.c_int]),
        "vn_method_reference": (c.c_char_p, [c.c_int]),
        "vn_method_from_name": (c.c_int, [c.c_char_p, _P(c.c_int)]),
        "vn_weld_positions": (c.c_int, [c.c_void_p, _P(_Positions), c.c_double, _P(_Options)]),
        "vn_polygon_corner_normals": (c.c_int, [_P(_Vectors), _P(_Positions), c.c_void_p, c.c_void_p,
                                                c.c_size_t, c.c_int, c.c_double, c.c_void_p,
                                                _P(_Options), _P(_Stats)]),
    }
    for name, (restype, argtypes) in sigs.items():
        try:
            f = getattr(lib, name)
        except AttributeError:
            raise VnError("the vn library lacks %s (an older vn build)" % name) from None
        f.restype = restype
        f.argtypes = argtypes


def _exports(path, symbol):
    """Whether the ELF shared library at path defines symbol in its dynamic
    symbol table (read from the file: 64-bit little-endian, as on x86-64)."""
    import struct
    with open(path, "rb") as f:
        data = f.read()
    if data[:4] != b"\x7fELF" or data[4] != 2 or data[5] != 1:
        return False
    shoff, = struct.unpack_from("<Q", data, 0x28)
    shentsize, shnum = struct.unpack_from("<HH", data, 0x3A)
    sections = [struct.unpack_from("<IIQQQQIIQQ", data, shoff + i * shentsize) for i in range(shnum)]
    for _name, kind, _flags, _addr, offset, size, link, _info, _align, entsize in sections:
        if kind != 11 or not entsize:  # SHT_DYNSYM
            continue
        strtab = sections[link][4]
        for k in range(offset, offset + size, entsize):
            st_name, _st_info, _st_other, st_shndx = struct.unpack_from("<IBBH", data, k)
            end = data.index(b"\0", strtab + st_name)
            if st_shndx != 0 and data[strtab + st_name:end] == symbol:
                return True
    return False


class Library:
    """One loaded copy of libvn."""

    def __init__(self, path):
        self.path = path
        if os.path.isdir(path):
            raise VnError("cannot load the vn library: %s is a directory, not libvn.so" % path)
        if not os.path.isfile(path):
            raise VnError("cannot load the vn library: %s does not exist" % path)
        # Checked before dlopen, which would run any other library's
        # constructors and load its dependencies (Qt for MeshLab's plugin).
        if not _exports(path, b"vn_version"):
            raise VnError("%s is not a vn library: it does not export vn_version" % path)
        try:
            self._lib = ctypes.CDLL(path)
        except OSError as e:
            raise VnError("cannot load the vn library %s: %s" % (path, e)) from None
        _declare(self._lib)
        v = self._lib.vn_version()
        self.version = self._lib.vn_version_string().decode()
        if EXPECTED_ABI is not None and (v >> 16, (v >> 8) & 0xFF) != EXPECTED_ABI:
            raise VnError("the vn library %s is version %s; this add-on needs version %d.%d"
                          % (path, self.version) + EXPECTED_ABI)
        self.methods = []  # (name, description, reference), in vn_method order
        i = 0
        while True:
            name = self._lib.vn_method_name(i)
            if name is None:
                break
            self.methods.append((name.decode(), (self._lib.vn_method_description(i) or b"").decode(),
                                 (self._lib.vn_method_reference(i) or b"").decode()))
            i += 1

    def _check(self, r, what):
        if r != 0:
            raise VnError("%s: %s" % (what, self._lib.vn_result_string(r).decode()))

    def method_index(self, name):
        out = ctypes.c_int()
        self._check(self._lib.vn_method_from_name(name.encode(), ctypes.byref(out)), "method %r" % name)
        return out.value

    @staticmethod
    def _positions(co):
        co = np.ascontiguousarray(co)
        if co.dtype not in (np.float32, np.float64) or co.ndim != 2 or co.shape[1] != 3:
            co = np.ascontiguousarray(co, dtype=np.float64).reshape(-1, 3)
        t = _FLOAT32 if co.dtype == np.float32 else _FLOAT64
        return co, _Positions(co.ctypes.data, co.shape[0], 0, t)

    @staticmethod
    def _options(threads):
        o = _Options()
        o.threads = (os.cpu_count() or 1) if threads is None else threads
        return o

    def weld_positions(self, co, epsilon, threads=None):
        """remap[i]: the representative of vertex i among vertices within epsilon."""
        co, pos = self._positions(co)
        remap = np.empty(pos.count, dtype=np.uint32)
        opt = self._options(threads)
        self._check(self._lib.vn_weld_positions(remap.ctypes.data, ctypes.byref(pos), float(epsilon),
                                                ctypes.byref(opt)), "vn_weld_positions")
        return remap

    def polygon_corner_normals(self, co, corner_vert, face_offsets, method, crease_angle=np.pi,
                               sharp_edges=None, threads=None, dtype=np.float64, face_strength=None):
        """Per-corner unit normals (dtype float64 or float32, one row per
        corner) of a polygon mesh: vn_polygon_corner_normals. method: a name
        or vn_method index; sharp_edges: one flag (bool or uint8) per corner
        (its edge to the next corner) or None; face_strength: one int32 per
        face or None (Face Influence: vn_options.face_strength). Arrays
        already of the types the library takes (float32/float64 (n, 3)
        positions, uint32 indices and offsets, int32 strengths, contiguous)
        are passed as they are, not copied."""
        if isinstance(method, str):
            method = self.method_index(method)
        co, pos = self._positions(co)
        idx = np.ascontiguousarray(corner_vert, dtype=np.uint32)
        off = np.ascontiguousarray(face_offsets, dtype=np.uint32)
        if off.ndim != 1 or off.size < 1 or int(off[-1]) != idx.size:
            raise VnError("face offsets must end at the number of corners")
        sharp = None
        if sharp_edges is not None:
            sharp = np.ascontiguousarray(sharp_edges)
            sharp = sharp.view(np.uint8) if sharp.dtype == np.bool_ else sharp.astype(np.uint8, copy=False)
            if sharp.size != idx.size:
                raise VnError("one sharp-edge flag per corner is needed")
        strength = None
        if face_strength is not None:
            strength = np.ascontiguousarray(face_strength, dtype=np.int32)
            if strength.size != off.size - 1:
                raise VnError("one face strength per face is needed")
        if np.dtype(dtype) not in (np.float32, np.float64):
            raise VnError("normals are float32 or float64, not %s" % np.dtype(dtype))
        out = np.empty((idx.size, 3), dtype=dtype)
        vec = _Vectors(out.ctypes.data, 0, _FLOAT32 if out.dtype == np.float32 else _FLOAT64)
        opt = self._options(threads)
        opt.face_strength = None if strength is None else strength.ctypes.data
        stats = _Stats()
        self._check(self._lib.vn_polygon_corner_normals(
            ctypes.byref(vec), ctypes.byref(pos), idx.ctypes.data, off.ctypes.data, off.size - 1, int(method),
            float(crease_angle), None if sharp is None else sharp.ctypes.data, ctypes.byref(opt),
            ctypes.byref(stats)), "vn_polygon_corner_normals")
        self.last_stats = {f: getattr(stats, f) for f, _ in _Stats._fields_}
        return out


_loaded = {}


def load(path):
    """The Library at path, loaded once per path."""
    path = os.path.abspath(os.path.expanduser(path))
    lib = _loaded.get(path)
    if lib is None:
        lib = _loaded[path] = Library(path)
    return lib


def find(preference_path=""):
    """(path, origin) of the library to use: the VN_LIBRARY environment
    variable, else the add-on preference, else the copy bundled in the add-on."""
    env = os.environ.get(ENV_VAR, "")
    if env:
        return env, "the %s environment variable" % ENV_VAR
    if preference_path:
        return preference_path, "the add-on preference"
    return BUNDLED, "the add-on's bundled copy"


def load_configured(preference_path=""):
    path, origin = find(preference_path)
    try:
        return load(path)
    except VnError as e:
        raise VnError("%s (library path from %s)" % (e, origin)) from None
