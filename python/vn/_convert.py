"""vn.convert: one file's conversion through libvnio.so's vn_io_convert
(src/io/vn_convert.h), the entry point vnconvert calls, so that options,
checks, messages and output bytes are vnconvert's.

libvnio.so is looked for in this order: the file named by the
``VN_LIBVNIO`` environment variable; libvnio.so in the folder of the libvn
in use (`vn.library`: ``VN_LIBRARY``'s folder, the package's lib folder,
the installed prefix or the build tree); the dynamic loader's search path.
"""

import ctypes
import os
import threading

from . import _binding
from ._binding import Error

ENV_VAR = "VN_LIBVNIO"
_c = ctypes


# vn_convert.h's structs, field for field (tests/python/test_convert.py
# checks every offset against the C compiler's).
class _ConvertOptions(_c.Structure):
    _fields_ = [("input_format", _c.c_char_p), ("output_format", _c.c_char_p), ("method", _c.c_char_p),
                ("threads", _c.c_uint), ("in_place", _c.c_int), ("no_weld", _c.c_int),
                ("weld_epsilon", _c.c_double), ("crease", _c.c_int), ("crease_angle", _c.c_double),
                ("weld_scope", _c.c_char_p), ("tangents", _c.c_char_p), ("draco", _c.c_char_p),
                ("meshopt", _c.c_char_p), ("draco_qp", _c.c_int), ("draco_qn", _c.c_int), ("draco_qt", _c.c_int),
                ("draco_qc", _c.c_int), ("draco_cl_set", _c.c_int), ("draco_cl", _c.c_int),
                ("apply_transforms", _c.c_int), ("stats", _c.c_int), ("ignore_misfits", _c.c_int),
                ("image_names_from_output", _c.c_int), ("input_is_copy", _c.c_int),
                ("progress", _c.c_void_p), ("progress_context", _c.c_void_p)]


class _ConvertReport(_c.Structure):
    _fields_ = [("warnings", _c.c_char_p), ("stats", _c.c_char_p), ("input_format", _c.c_char_p),
                ("output_format", _c.c_char_p), ("method", _c.c_char_p), ("threads", _c.c_uint),
                ("vertices", _c.c_size_t), ("faces", _c.c_size_t), ("triangles", _c.c_size_t),
                ("welded_vertices", _c.c_size_t), ("hard_edges", _c.c_size_t), ("split_vertices", _c.c_size_t),
                ("zero_normals", _c.c_size_t), ("degenerate_faces", _c.c_size_t),
                ("read_seconds", _c.c_double), ("normals_seconds", _c.c_double), ("write_seconds", _c.c_double),
                ("seconds", _c.c_double), ("draco_normals_compared", _c.c_size_t),
                ("draco_normal_bits", _c.c_int), ("draco_normal_median_degrees", _c.c_double),
                ("draco_normal_max_degrees", _c.c_double)]


class _BatchFile(_c.Structure):
    _fields_ = [("input", _c.c_char_p), ("output", _c.c_char_p), ("input_format", _c.c_char_p),
                ("output_format", _c.c_char_p)]


class _BatchPlan(_c.Structure):
    _fields_ = [("files", _c.POINTER(_BatchFile)), ("count", _c.c_size_t), ("skipped", _c.c_size_t),
                ("unentered", _c.c_size_t)]


class _Error(_c.Structure):
    _fields_ = [("message", _c.c_char * 512)]


class Report:
    """What `convert` did: vn_convert_report's fields as attributes.

    Attributes
    ----------
    warnings : list of str
        What vnconvert prints as warnings, one line each, without
        "vnconvert: warning: ".
    stats : str or None
        With ``stats=True``, what ``vnconvert --stats`` prints; else None.
    input_format, output_format, method : str
        As resolved ("off", "glb", "mwa").
    threads : int
    vertices, faces : int
        Read (glTF to glTF: of the primitives processed).
    triangles : int
        Written (polygons fan-triangulated).
    welded_vertices, hard_edges, split_vertices, zero_normals, degenerate_faces : int
    read_seconds, normals_seconds, write_seconds, seconds : float
        The three steps (0 on the glTF to glTF path) and the whole conversion.
    draco_normals_compared, draco_normal_bits : int
    draco_normal_median_degrees, draco_normal_max_degrees : float
        Draco output with ``stats=True``: the angle normal quantization adds.
    """

    def __init__(self, r):
        for name, _ in _ConvertReport._fields_:
            value = getattr(r, name)
            setattr(self, name, value.decode(errors="replace") if isinstance(value, bytes) else value)
        self.warnings = self.warnings.splitlines() if self.warnings else []

    def __repr__(self):
        return "vn.Report(%s)" % ", ".join("%s=%r" % kv for kv in vars(self).items())


class IoLibrary:
    """One loaded copy of libvnio."""

    def __init__(self, path, check_exports=True):
        self.path = path
        if check_exports:
            if not os.path.isfile(path):
                raise Error("cannot load the vn I/O library: %s does not exist" % path)
            if not _binding._exports(path, b"vn_io_convert"):
                raise Error("%s is not vn's I/O library: it does not export vn_io_convert" % path)
        try:
            lib = _c.CDLL(path)
        except OSError as e:
            raise Error("cannot load the vn I/O library %s: %s" % (path, e)) from None
        P = _c.POINTER
        lib.vn_io_convert.restype = _c.c_int
        lib.vn_io_convert.argtypes = [_c.c_char_p, _c.c_char_p, P(_ConvertOptions), P(_ConvertReport), P(_Error)]
        lib.vn_io_convert_report_free.restype = None
        lib.vn_io_convert_report_free.argtypes = [P(_ConvertReport)]
        lib.vn_io_convert_option.restype = _c.c_int
        lib.vn_io_convert_option.argtypes = [P(_ConvertOptions), _c.c_char_p, _c.c_char_p, P(_Error)]
        lib.vn_io_convert_option_arity.restype = _c.c_int
        lib.vn_io_convert_option_arity.argtypes = [_c.c_char_p]
        lib.vn_io_batch_plan.restype = _c.c_int
        lib.vn_io_batch_plan.argtypes = [P(_c.c_char_p), _c.c_size_t, _c.c_char_p, _c.c_int, P(_ConvertOptions),
                                         P(_BatchPlan), P(_Error)]
        lib.vn_io_batch_plan_free.restype = None
        lib.vn_io_batch_plan_free.argtypes = [P(_BatchPlan)]
        self._lib = lib

    def arity(self, flag):
        """1 when vnconvert flag `flag` ("--draco-qp") takes a value, 0 for
        a switch, -1 when it is no option of a conversion."""
        return self._lib.vn_io_convert_option_arity(flag.encode())

    def options(self, method, options):
        """A vn_convert_options set flag by flag as vnconvert's command line
        sets it: keyword crease_angle is --crease-angle; a switch is given
        as True (False leaves it out), a value as its str(); None is the
        default. stats=True fills Report.stats (vnconvert --stats)."""
        o, error = _ConvertOptions(), _Error()
        if isinstance(getattr(method, "name", None), str):  # a vn.Method
            method = method.name
        flags = [("method", method)] + list(options.items())
        for key, value in flags:
            if key == "stats":
                o.stats = bool(value)
                continue
            flag = ("--" + key.replace("_", "-")).encode()
            arity = self._lib.vn_io_convert_option_arity(flag)
            if arity < 0 or key != key.lower() or "-" in key:
                raise Error("convert() has no option %s (vnconvert has no %s)" % (key, flag.decode()))
            if value is None or value is False:
                continue
            if arity == 0 and value is not True:
                raise Error("option %s is a switch: True or False, not %r" % (key, value))
            text = None if arity == 0 else str(value).encode()
            if self._lib.vn_io_convert_option(_c.byref(o), flag, text, _c.byref(error)):
                raise Error(error.message.decode(errors="replace"))
        return o

    def plan(self, inputs, out_dir, recursive, options):
        """vn_io_batch_plan: ([(input, output, input_format, output_format)],
        skipped, unentered), paths as str; the output folders are made."""
        paths = [os.fsencode(p) for p in inputs]
        array = (_c.c_char_p * max(len(paths), 1))(*paths)
        plan, error = _BatchPlan(), _Error()
        if self._lib.vn_io_batch_plan(array, len(paths), os.fsencode(out_dir), int(bool(recursive)),
                                      _c.byref(options), _c.byref(plan), _c.byref(error)):
            raise Error(error.message.decode(errors="replace"))
        try:
            files = [(os.fsdecode(f.input), os.fsdecode(f.output), f.input_format.decode(), f.output_format.decode())
                     for f in plan.files[:plan.count]]
            return files, plan.skipped, plan.unentered
        finally:
            self._lib.vn_io_batch_plan_free(_c.byref(plan))

    def convert(self, src, dst, options):
        report, error = _ConvertReport(), _Error()
        try:
            r = self._lib.vn_io_convert(os.fsencode(src), os.fsencode(dst), _c.byref(options), _c.byref(report),
                                        _c.byref(error))
            result = Report(report)
        finally:
            self._lib.vn_io_convert_report_free(_c.byref(report))
        if r:
            raise Error(error.message.decode(errors="replace"))
        return result


_lock = threading.Lock()
_loaded = {}


def io_library(libvn_path):
    """The IoLibrary to use beside the libvn at libvn_path (see the module's
    docstring), loaded once per path."""
    env = os.environ.get(ENV_VAR, "")
    if env:
        path, origin, check = os.path.abspath(env), "the %s environment variable" % ENV_VAR, True
    elif os.path.isabs(libvn_path):
        path, origin, check = os.path.join(os.path.dirname(libvn_path), "libvnio.so"), "libvn's folder", True
        if not os.path.exists(path):  # an installed prefix without the development link
            path = os.path.join(os.path.dirname(libvn_path), "libvnio.so.%d.%d" % _binding.ABI)
    else:
        path, origin, check = "libvnio.so.%d.%d" % _binding.ABI, "the loader's path", False
    with _lock:
        lib = _loaded.get(path)
        if lib is None:
            try:
                lib = _loaded[path] = IoLibrary(path, check)
            except Error as e:
                raise Error("%s (library path from %s)" % (e, origin)) from None
    return lib
