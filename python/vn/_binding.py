"""ctypes binding of vn's shared library (src/vn.h), with numpy arrays.

Pure Python, no bpy: the vn package and the Blender add-on both use this
file (the build copies it into the add-on as binding.py). Every function
used is declared with argtypes/restype; a vn_result other than success is
raised as Error carrying the library's own message (vn_result_string).
ctypes releases the GIL for the duration of each call.
"""

import ctypes
import os
import threading

import numpy as np

# The vn.h this binding's structs copy (tests/python checks it against src/vn.h).
VERSION = "0.3.0"
# Before 1.0 the ABI is the major and minor version's (vn.h, vn_version).
ABI = tuple(int(x) for x in VERSION.split(".")[:2])
ENV_VAR = "VN_LIBRARY"
HERE = os.path.dirname(os.path.abspath(__file__))
BUNDLED = os.path.join(HERE, "lib", "libvn.so")


class Error(ValueError):
    """A vn call failed (bad input, with the library's message), or the
    library could not be loaded."""


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
_UINT32_MAX = 0xFFFFFFFF


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
        "vn_workspace_size": (c.c_size_t, [c.c_size_t, _P(_Options)]),
        "vn_weld_positions": (c.c_int, [c.c_void_p, _P(_Positions), c.c_double, _P(_Options)]),
        "vn_triangle_normals": (c.c_int, [_P(_Vectors), _P(_Positions), c.c_void_p, c.c_size_t, c.c_int,
                                          _P(_Options), _P(_Stats)]),
        "vn_polygon_normals": (c.c_int, [_P(_Vectors), _P(_Positions), c.c_void_p, c.c_void_p, c.c_size_t,
                                         c.c_int, _P(_Options), _P(_Stats)]),
        "vn_corner_normals": (c.c_int, [_P(_Vectors), _P(_Positions), c.c_void_p, c.c_size_t, c.c_int,
                                        c.c_double, c.c_void_p, _P(_Options), _P(_Stats)]),
        "vn_polygon_corner_normals": (c.c_int, [_P(_Vectors), _P(_Positions), c.c_void_p, c.c_void_p,
                                                c.c_size_t, c.c_int, c.c_double, c.c_void_p,
                                                _P(_Options), _P(_Stats)]),
        "vn_plan_create": (c.c_int, [c.c_void_p, c.c_void_p, c.c_size_t, c.c_size_t, _P(_Options),
                                     _P(c.c_void_p)]),
        "vn_plan_destroy": (None, [c.c_void_p]),
        "vn_plan_normals": (c.c_int, [c.c_void_p, _P(_Positions), c.c_int, _P(_Vectors), _P(_Stats)]),
        "vn_plan_corner_normals": (c.c_int, [c.c_void_p, _P(_Positions), c.c_int, c.c_double, c.c_void_p,
                                             _P(_Vectors), _P(_Stats)]),
    }
    for name, (restype, argtypes) in sigs.items():
        try:
            f = getattr(lib, name)
        except AttributeError:
            raise Error("the vn library lacks %s (an older vn build)" % name) from None
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


def _rows(a):
    """The byte stride between the (x, y, z) rows of a float32/float64 (n, 3)
    array whose rows the library can read in place, else None."""
    if a.dtype not in (np.float32, np.float64) or a.ndim != 2 or a.shape[1] != 3:
        return None
    if a.shape[0] == 0:
        return 0
    if (a.strides[1] != a.itemsize or (a.shape[0] > 1 and a.strides[0] < 3 * a.itemsize)
            or not a.flags.aligned):
        return None  # interleaved columns, reversed or broadcast rows, packed records
    return a.strides[0]


def _indices(a, what):
    """a as contiguous uint32: read in place when it is uint32, or int32
    without a negative value (Open3D's triangles), else copied once. Values
    that do not fit (negative, above 2^32 - 1) are refused here, before a
    cast could wrap them onto valid vertices."""
    a = np.asarray(a)
    if a.dtype == np.uint32:
        return np.ascontiguousarray(a).ravel()
    if a.size and a.dtype.kind not in "iu":
        raise Error("%s must be integers, not %s" % (what, a.dtype))
    # One pass: the bits of every value OR-ed show a sign or a bit above 31.
    if a.size and int(np.bitwise_or.reduce(a, axis=None)) & ~_UINT32_MAX:
        raise Error("%s: index out of range (%d)" % (what, a.min() if a.min() < 0 else a.max()))
    if a.dtype == np.int32:
        return np.ascontiguousarray(a).ravel().view(np.uint32)
    return np.ascontiguousarray(a, dtype=np.uint32).ravel()


class Library:
    """One loaded copy of libvn."""

    def __init__(self, path, check_exports=True):
        self.path = path
        # Each Python thread's work memory for vertex normals, kept from call
        # to call: a call then allocates (and page-faults) nothing of its own.
        self._workspaces = threading.local()
        if check_exports:
            if os.path.isdir(path):
                raise Error("cannot load the vn library: %s is a directory, not libvn.so" % path)
            if not os.path.isfile(path):
                raise Error("cannot load the vn library: %s does not exist" % path)
            # Checked before dlopen, which would run any other library's
            # constructors and load its dependencies (Qt for MeshLab's plugin).
            if not _exports(path, b"vn_version"):
                raise Error("%s is not a vn library: it does not export vn_version" % path)
        try:
            self._lib = ctypes.CDLL(path)
        except OSError as e:
            raise Error("cannot load the vn library %s: %s" % (path, e)) from None
        _declare(self._lib)
        v = self._lib.vn_version()
        self.version = self._lib.vn_version_string().decode()
        if (v >> 16, (v >> 8) & 0xFF) != ABI:
            raise Error("the vn library %s is version %s; this binding needs version %d.%d"
                        % ((path, self.version) + ABI))
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
            raise Error("%s: %s" % (what, self._lib.vn_result_string(r).decode()))

    def method_index(self, name):
        """The vn_method of a name (any case), of an entry of vn.methods(), or of an index already."""
        if isinstance(getattr(name, "name", None), str):  # a vn.Method
            name = name.name
        if not isinstance(name, str):
            if not isinstance(name, (int, np.integer)) or not 0 <= name < len(self.methods):
                self._check(3, "method %r" % (name,))  # vn_result_unknown_method
            return int(name)
        out = ctypes.c_int()
        self._check(self._lib.vn_method_from_name(name.encode(), ctypes.byref(out)), "method %r" % name)
        return out.value

    @staticmethod
    def _positions(co):
        """(array kept alive, vn_positions): float32/float64 rows read in
        place with their byte stride, anything else converted once to float64.
        A flat array is read as x, y, z triples."""
        co = np.asarray(co)
        if co.ndim == 1 and co.size % 3 == 0:
            co = co.reshape(-1, 3)
        stride = _rows(co)
        if stride is None:
            if co.ndim != 2 or co.shape[1] != 3:
                raise Error("positions must be an (n, 3) array, not of shape %s" % (co.shape,))
            if co.dtype.kind not in "fiub":
                raise Error("positions must be numbers, not %s" % co.dtype)
            co = np.ascontiguousarray(co, dtype=np.float64)
            stride = co.strides[0]
        return co, _Positions(co.ctypes.data, co.shape[0], stride, _FLOAT32 if co.dtype == np.float32 else _FLOAT64)

    @staticmethod
    def _vectors(out, rows, dtype):
        """(array, vn_vectors) for rows unit vectors: out itself, written in
        place through its byte stride, or a new array of dtype."""
        if out is None:
            if np.dtype(dtype) not in (np.float32, np.float64):
                raise Error("normals are float32 or float64, not %s" % np.dtype(dtype))
            out = np.empty((rows, 3), dtype=dtype)
        stride = _rows(out)
        if stride is None or out.shape[0] != rows or not out.flags.writeable:
            raise Error("out must be a writable (%d, 3) float32 or float64 array with contiguous rows, "
                        "not %s %s" % (rows, out.dtype, out.shape))
        return out, _Vectors(out.ctypes.data, stride, _FLOAT32 if out.dtype == np.float32 else _FLOAT64)

    @staticmethod
    def _options(threads):
        """threads None or 0: one per core (results do not depend on it)."""
        o = _Options()
        o.threads = threads or os.cpu_count() or 1
        return o

    def _workspace(self, vertex_count, options):
        """Sets options' workspace to this thread's, grown to what a call
        for vertex_count vertices needs (kept: the largest mesh's ~32 bytes
        a vertex)."""
        size = self._lib.vn_workspace_size(vertex_count, ctypes.byref(options))
        buffer = getattr(self._workspaces, "buffer", None)
        if buffer is None or buffer.size < size:
            buffer = self._workspaces.buffer = np.empty(size, dtype=np.uint8)
        options.workspace, options.workspace_size = buffer.ctypes.data, buffer.size

    @staticmethod
    def _offsets(face_offsets, index_count):
        off = _indices(face_offsets, "face offsets")
        if off.size < 1 or int(off[-1]) != index_count:
            raise Error("face offsets must end at the number of corners (%d)" % index_count)
        return off

    def weld_positions(self, co, epsilon, threads=None):
        """remap[i] (uint32): the representative of vertex i among vertices
        within epsilon (vn_weld_positions)."""
        if not 0 <= epsilon < np.inf:
            raise Error("weld epsilon %r: must be a finite distance, 0 or more" % epsilon)
        co, pos = self._positions(co)
        remap = np.empty(pos.count, dtype=np.uint32)
        opt = self._options(threads)
        self._check(self._lib.vn_weld_positions(remap.ctypes.data, ctypes.byref(pos), float(epsilon),
                                                ctypes.byref(opt)), "vn_weld_positions")
        return remap

    def vertex_normals(self, co, corner_vert, face_offsets, method, threads=None, out=None, stats=True):
        """(normals, stats): unit normals per vertex, (n, 3) float64 or
        written into out (float32 or float64 rows), and vn_stats as a dict
        (None with stats False: the library then skips counting).
        face_offsets None: triangles (vn_triangle_normals), else polygons
        (vn_polygon_normals)."""
        method = self.method_index(method)
        co, pos = self._positions(co)
        idx = _indices(corner_vert, "faces")
        out, vec = self._vectors(out, pos.count, np.float64)
        opt, counts = self._options(threads), _Stats() if stats else None
        self._workspace(pos.count, opt)
        counted = None if counts is None else ctypes.byref(counts)
        off, faces = self._faces(idx, face_offsets)
        if off is None:
            r = self._lib.vn_triangle_normals(ctypes.byref(vec), ctypes.byref(pos), idx.ctypes.data, idx.size,
                                              method, ctypes.byref(opt), counted)
            self._check(r, "vn_triangle_normals")
        else:
            r = self._lib.vn_polygon_normals(ctypes.byref(vec), ctypes.byref(pos), idx.ctypes.data, off.ctypes.data,
                                             faces, method, ctypes.byref(opt), counted)
            self._check(r, "vn_polygon_normals")
        return out, _stats_dict(counts)

    def corner_normals(self, co, corner_vert, face_offsets, method, crease_angle=np.pi,
                       sharp_edges=None, threads=None, dtype=np.float64, face_strength=None):
        """(normals, stats): unit normals per corner (dtype float64 or
        float32, one row per corner) and vn_stats as a dict. face_offsets
        None: triangles (vn_corner_normals), else polygons
        (vn_polygon_corner_normals). method: a name or vn_method index;
        sharp_edges: one flag (bool or uint8) per corner (its edge to the next
        corner) or None; face_strength: one int32 per face or None (Face
        Influence: vn_options.face_strength). Arrays already of the types the
        library takes (float32/float64 (n, 3) positions, uint32 indices and
        offsets, int32 strengths, contiguous) are passed as they are, not
        copied."""
        method = self.method_index(method)
        crease = _crease(crease_angle)
        co, pos = self._positions(co)
        idx = _indices(corner_vert, "faces")
        off, faces = self._faces(idx, face_offsets)
        sharp = _sharp(sharp_edges, idx.size)
        strength = _strength(face_strength, faces)
        out, vec = self._vectors(None, idx.size, dtype)
        opt, stats = self._options(threads), _Stats()
        opt.face_strength = None if strength is None else strength.ctypes.data
        sharp_p = None if sharp is None else sharp.ctypes.data
        if off is None:
            r = self._lib.vn_corner_normals(ctypes.byref(vec), ctypes.byref(pos), idx.ctypes.data, idx.size, method,
                                            crease, sharp_p, ctypes.byref(opt), ctypes.byref(stats))
            self._check(r, "vn_corner_normals")
        else:
            r = self._lib.vn_polygon_corner_normals(
                ctypes.byref(vec), ctypes.byref(pos), idx.ctypes.data, off.ctypes.data, faces, method,
                crease, sharp_p, ctypes.byref(opt), ctypes.byref(stats))
            self._check(r, "vn_polygon_corner_normals")
        return out, _stats_dict(stats)

    def _faces(self, idx, face_offsets):
        """(offsets or None, face count) of corner indices idx."""
        if face_offsets is None:
            if idx.size % 3:
                raise Error("triangles need 3 indices each, not %d in all" % idx.size)
            return None, idx.size // 3
        off = self._offsets(face_offsets, idx.size)
        return off, off.size - 1

    def plan(self, corner_vert, face_offsets=None, vertex_count=None, threads=None, face_strength=None):
        """A Plan of these faces (vn_plan_create)."""
        return Plan(self, corner_vert, face_offsets, vertex_count, threads, face_strength)


def _crease(crease_angle):
    if not crease_angle >= 0:
        raise Error("crease angle %r: must be 0 or more radians (pi and more: no crease)" % crease_angle)
    return float(crease_angle)


def _sharp(sharp_edges, corners):
    """sharp_edges as contiguous uint8 (bool read in place), or None."""
    if sharp_edges is None:
        return None
    sharp = np.ascontiguousarray(sharp_edges)
    sharp = sharp.view(np.uint8) if sharp.dtype == np.bool_ else sharp.astype(np.uint8, copy=False)
    if sharp.size != corners:
        raise Error("one sharp-edge flag per corner is needed: %d flags, %d corners" % (sharp.size, corners))
    return sharp.ravel()


def _strength(face_strength, faces):
    if face_strength is None:
        return None
    strength = np.ascontiguousarray(face_strength, dtype=np.int32)
    if strength.size != faces:
        raise Error("one face strength per face is needed: %d strengths, %d faces" % (strength.size, faces))
    return strength.ravel()


def _stats_dict(stats):
    return None if stats is None else {f: getattr(stats, f) for f, _ in _Stats._fields_}


class Plan:
    """A vn_plan: faces checked and laid out once (vn_plan_create), then
    normals of any number of position sets with no check, copy or
    allocation of their own. One call runs at a time (a lock: the plan has
    one work area); close() frees it, as does garbage collection."""

    def __init__(self, lib, corner_vert, face_offsets=None, vertex_count=None, threads=None, face_strength=None):
        self._lib = lib
        self._handle = None
        self._lock = threading.Lock()
        idx = _indices(corner_vert, "faces")
        off, self.face_count = lib._faces(idx, face_offsets)
        self.corner_count = idx.size
        if vertex_count is None:
            vertex_count = int(idx.max()) + 1 if idx.size else 0
        if not isinstance(vertex_count, (int, np.integer)) or not 0 <= vertex_count <= _UINT32_MAX:
            raise Error("vertex count %r: must be an integer from 0 to %d" % (vertex_count, _UINT32_MAX))
        self.vertex_count = int(vertex_count)
        # vn_plan_corner_normals reads the strengths at each call: the plan
        # owns this array, and a caller may change its values in place.
        strength = _strength(face_strength, self.face_count)
        self._strength = None if strength is None else strength.copy()
        opt = lib._options(threads)
        opt.face_strength = None if strength is None else self._strength.ctypes.data
        handle = ctypes.c_void_p()
        r = lib._lib.vn_plan_create(idx.ctypes.data, None if off is None else off.ctypes.data, self.face_count,
                                    self.vertex_count, ctypes.byref(opt), ctypes.byref(handle))
        if r == 2:  # vn_result_index_out_of_range: say which
            raise Error("faces: index %d out of range for %d vertices" % (int(idx.max()), self.vertex_count))
        if r == 1 and off is not None and (np.diff(off.astype(np.int64)) < 0).any():
            raise Error("face offsets must not decrease")
        lib._check(r, "vn_plan_create")
        self._handle = handle

    def close(self):
        """Frees the plan's memory; later calls raise Error. Calling it again does nothing."""
        with self._lock:
            if self._handle is not None:
                self._lib._lib.vn_plan_destroy(self._handle)
                self._handle = None

    def __del__(self):
        if getattr(self, "_handle", None) is not None:
            self.close()

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

    @property
    def closed(self):
        return self._handle is None

    @property
    def face_strength(self):
        """The int32 strengths the plan reads at each corner_normals call
        (None: no Face Influence); change them in place, not the array."""
        return self._strength

    def _call(self, name, co, out, dtype_out, rows, stats, *args):
        """Runs vn_plan_<name> on positions co: (out, stats dict or None).
        The output's dtype follows the positions' (float32 or float64)
        unless out or dtype_out says otherwise."""
        co, pos = self._lib._positions(co)
        if pos.count != self.vertex_count:
            raise Error("positions: %d vertices; this plan's faces are over %d" % (pos.count, self.vertex_count))
        if dtype_out is None:
            dtype_out = np.float32 if pos.type == _FLOAT32 else np.float64
        out, vec = self._lib._vectors(out, rows, dtype_out)
        counts = _Stats() if stats else None
        with self._lock:
            if self._handle is None:
                raise Error("this plan is closed")
            f = getattr(self._lib._lib, "vn_plan_" + name)
            r = f(self._handle, ctypes.byref(pos), *args, ctypes.byref(vec),
                  None if counts is None else ctypes.byref(counts))
        self._lib._check(r, "vn_plan_" + name)
        return out, _stats_dict(counts)

    def normals(self, co, method, out=None, dtype=None, stats=False):
        """(normals, stats): per vertex, as vertex_normals computes them
        (vn_plan_normals); written into out when given, else a new array of
        dtype (default: the positions' float32 or float64)."""
        return self._call("normals", co, out, dtype, self.vertex_count, stats, self._lib.method_index(method))

    def corner_normals(self, co, method, crease_angle=np.pi, sharp_edges=None, out=None, dtype=None, stats=False):
        """(normals, stats): per corner, as corner_normals computes them
        (vn_plan_corner_normals); face strengths are the plan's."""
        sharp = _sharp(sharp_edges, self.corner_count)
        return self._call("corner_normals", co, out, dtype, self.corner_count, stats,
                          self._lib.method_index(method), _crease(crease_angle),
                          None if sharp is None else sharp.ctypes.data)


_loaded = {}


def load(path, check_exports=True):
    """The Library at path, loaded once per path. check_exports False: path
    may be a bare soname for the dynamic loader to find."""
    if check_exports:
        path = os.path.abspath(os.path.expanduser(path))
    lib = _loaded.get(path)
    if lib is None:
        lib = _loaded[path] = Library(path, check_exports)
    return lib


def find(preference_path=""):
    """(path, origin) of the library to use: the VN_LIBRARY environment
    variable, else the add-on preference, else the copy bundled beside this
    file (the add-on's lib/libvn.so)."""
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
    except Error as e:
        raise Error("%s (library path from %s)" % (e, origin)) from None
