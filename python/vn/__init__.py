"""vn: vertex normals with every weighting scheme of Jin, Lewis & West 2005.

numpy arrays in, numpy arrays out, computed by vn's C library (libvn)
through ctypes: exact in double precision, multithreaded, and with the GIL
released during the computation, so Python threads run side by side.

Functions
---------
methods         the schemes: name, description, reference
vertex_normals  one unit normal per vertex
corner_normals  one unit normal per face corner, split at sharp edges
Plan            faces prepared once for the normals of many frames
weld            the representative vertex of each position
convert         a mesh file to another format with new normals, as vnconvert
                (a batch into a folder with out_dir; on a Dask cluster: vn.dask)

Meshes are given as ``positions, faces`` or as one object: anything with
``.vertices`` and ``.faces`` (trimesh), an Open3D ``TriangleMesh``
(``.vertices`` and ``.triangles``) or a meshio ``Mesh`` (``.points`` and
triangle, quad and polygon ``.cells``). `vn.open3d.set_normals` writes the
normals back into an Open3D mesh.

The library is looked for in this order: the file named by the
``VN_LIBRARY`` environment variable; ``lib/libvn.so`` beside this package;
the library ``cmake --install`` put beside it; ``build/libvn.so`` of the
source tree this package is in; the dynamic loader's search path. `convert`
uses libvnio.so: the file named by ``VN_LIBVNIO``, else the one in libvn's
folder.
"""

import collections
import os

import numpy as np

from . import _batch, _binding, _convert
from ._binding import Error
from ._batch import Batch, FileResult
from ._convert import Report

__all__ = ["Batch", "Error", "FileResult", "Method", "Plan", "Report", "convert", "corner_normals", "library", "methods", "open3d", "vertex_normals", "weld"]
__version__ = _binding.VERSION

Method = collections.namedtuple("Method", "name description reference")
Method.__doc__ = "A weighting scheme: its name (for method=), what it weights by, where it comes from."


def _installed():
    """The library path ``cmake --install`` wrote beside the package, or None."""
    try:
        from . import _install
    except ImportError:
        return None
    return os.path.normpath(os.path.join(_binding.HERE, _install.LIBRARY))


def library():
    """The loaded libvn (`_binding.Library`): its ``path`` and ``version``.

    Raises
    ------
    Error
        When no library is found, or the one found is not a vn library of
        this package's version.
    """
    env = os.environ.get(_binding.ENV_VAR, "")
    if env:
        origins = [(env, "the %s environment variable" % _binding.ENV_VAR)]
    else:
        origins = [(_binding.BUNDLED, "the package's lib folder"), (_installed(), "the installed package"),
                   (os.path.join(_binding.HERE, os.pardir, os.pardir, "build", "libvn.so"), "the source tree")]
        origins = [(path, origin) for path, origin in origins if path and os.path.exists(path)]
    for path, origin in origins:
        try:
            return _binding.load(path)
        except Error as e:
            raise Error("%s (library path from %s)" % (e, origin)) from None
    soname = "libvn.so.%d.%d" % _binding.ABI
    try:
        return _binding.load(soname, check_exports=False)
    except Error:
        raise Error("the vn library was not found: build it (cmake --build build), install it (cmake --install "
                    "build) or set %s to the path of libvn.so (%s is not on the loader's path either)"
                    % (_binding.ENV_VAR, soname)) from None


def methods():
    """The weighting schemes, in the order of ``vnconvert --list-methods``.

    Returns
    -------
    list of Method
        ``(name, description, reference)`` named tuples; ``name`` is what
        ``method=`` takes (any case).

    Examples
    --------
    >>> [m.name for m in vn.methods()]
    ['mwe', 'mwa', 'mwselr', 'mwaat', 'mwelr', 'mwrelr', 'mewcsa', 'smewcsa', 'quadric', 'jet', 'adaptive']
    """
    return [Method(*m) for m in library().methods]


def _mesh(positions, faces):
    """(positions, faces) of a mesh object, or the two given."""
    if faces is not None:
        return positions, faces
    if hasattr(positions, "vertices") and hasattr(positions, "faces"):
        return positions.vertices, positions.faces
    if hasattr(positions, "vertices") and hasattr(positions, "triangles"):  # Open3D
        return np.asarray(positions.vertices), np.asarray(positions.triangles)
    if hasattr(positions, "points") and hasattr(positions, "cells"):  # meshio
        return positions.points, _meshio_faces(positions.cells)
    raise Error("faces are missing: give positions and faces, or a mesh with .vertices and .faces")


def _meshio_faces(cells):
    """The triangle, quad and polygon blocks of meshio cells, as one face
    array when they are all of one size, else as (indices, offsets). Other
    cell types (lines, volumes) have no surface normal and are left out."""
    blocks = []
    for block in cells:
        if block.type in ("triangle", "quad") or block.type.startswith("polygon"):
            data = block.data
            blocks.extend([np.asarray(data)] if np.ndim(data) == 2 else [np.asarray(f)[None] for f in data])
    if not blocks:
        raise Error("the meshio mesh has no triangle, quad or polygon cells")
    if len({b.shape[1] for b in blocks}) == 1:
        return np.concatenate(blocks)
    sizes = np.concatenate([np.full(len(b), b.shape[1]) for b in blocks])
    return np.concatenate([b.ravel() for b in blocks]), np.concatenate([[0], np.cumsum(sizes)])


def _faces(faces):
    """(indices, offsets, shape): offsets None for triangles; shape the
    faces' (m, k) shape, or None for polygons."""
    if isinstance(faces, tuple) and len(faces) == 2 and np.ndim(faces[0]) == 1 and np.ndim(faces[1]) == 1 \
            and len(faces[0]) != len(faces[1]):
        return faces[0], faces[1], None
    try:
        f = np.asarray(faces)
    except ValueError:  # numpy refuses a ragged list
        f = None
    if f is None or (f.dtype == object and f.ndim == 1):
        return _ragged(faces)
    if f.ndim != 2:
        raise Error("faces must be an (m, k) integer array or (indices, offsets), not of shape %s" % (f.shape,))
    if f.shape[1] == 3:
        return f, None, f.shape
    return f, np.arange(f.shape[0] + 1, dtype=np.int64) * f.shape[1], f.shape


def _positions(positions):
    if hasattr(positions, "vertices") or hasattr(positions, "points"):  # a mesh
        positions = positions.vertices if hasattr(positions, "vertices") else positions.points
    p = np.asarray(positions)
    if p.ndim != 2 or p.shape[1] != 3:
        raise Error("positions must be an (n, 3) array, not of shape %s" % (p.shape,))
    return p


def _ragged(faces):
    """Faces of mixed sizes given one by one (e.g. a list of lists) as
    (indices, offsets)."""
    rows = [np.asarray(x) for x in faces]
    if any(r.ndim != 1 for r in rows):
        raise Error("faces of mixed sizes must each be a sequence of corner indices")
    offsets = np.zeros(len(rows) + 1, dtype=np.int64)
    np.cumsum([len(r) for r in rows], out=offsets[1:])
    return np.concatenate(rows), offsets, None


def vertex_normals(positions, faces=None, method="mwa", *, threads=0, out=None):
    """Unit normals of the vertices of a mesh.

    Parameters
    ----------
    positions : (n, 3) array_like, or a mesh
        Vertex positions. float64 and float32 arrays are read in place (rows
        with any byte stride); anything else is converted once to float64.
        A mesh object instead: anything with ``.vertices`` and ``.faces``,
        an Open3D ``TriangleMesh`` or a meshio ``Mesh`` (then ``faces`` is
        left out).
    faces : (m, k) array_like of integers, or tuple (indices, offsets)
        Face corners counter-clockwise, any integer dtype. (m, 3) are
        triangles; (m, k) faces of k corners. Polygons of mixed sizes: the
        flat ``indices`` of every corner and ``offsets`` (m + 1 entries,
        face f is ``indices[offsets[f]:offsets[f + 1]]``); a tuple whose two
        parts have equal lengths is read as two faces instead. Or one
        sequence a face, e.g. ``[[0, 1, 2], [0, 2, 3, 4]]``.
    method : str or Method, default "mwa"
        A name from `methods` (any case), e.g. "mwselr" or "adaptive", or
        an entry of `methods`.
    threads : int, default 0
        Worker threads; 0 uses one per core, 1 the calling thread only.
        The result does not depend on it, bit for bit.
    out : (n, 3) float64 or float32 ndarray, optional
        Written in place (rows with any byte stride) and returned.

    Returns
    -------
    (n, 3) ndarray
        float64 unit normals (or `out`). A vertex no face contributes to
        (isolated, or only in degenerate faces or faces touching a NaN or
        infinite position) gets (0, 0, 0): never NaN.

    Raises
    ------
    Error
        Wrong shapes or types, an index out of range, an unknown method; the
        message is the library's. Nothing is written into `out` then.

    Examples
    --------
    >>> import numpy as np, vn
    >>> p = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0.]])
    >>> vn.vertex_normals(p, [[0, 1, 2, 3]])[0]
    array([0., 0., 1.])
    >>> vn.vertex_normals(p, [[0, 1, 2], [0, 2, 3]], "mwaat", threads=1)[2]
    array([0., 0., 1.])
    """
    positions, faces = _mesh(positions, faces)
    idx, off, _ = _faces(faces)
    return library().vertex_normals(_positions(positions), idx, off, method, threads, out, stats=False)[0]


def corner_normals(positions, faces=None, method="mwa", *, crease_angle=None, sharp_edges=None, threads=0):
    """Unit normals of the corners of a mesh's faces, split at sharp edges.

    A corner's normal sums the method's contributions of the faces around
    its vertex that are reached from the corner's face without crossing a
    sharp edge. An edge is sharp when it is a boundary or non-manifold edge,
    flagged in `sharp_edges`, or creased. Edges are identified by vertex
    index: weld first (`weld`) when a mesh splits vertices along seams.

    Parameters
    ----------
    positions, faces, method, threads
        As for `vertex_normals`.
    crease_angle : float, optional
        Radians: an edge whose two faces' normals differ by more is sharp.
        None (or pi and above): no crease. 0 makes every non-flat edge sharp.
    sharp_edges : array_like of bool, optional
        One flag per corner, shaped as `faces` (or flat, one per index): the
        edge from that corner to the next corner of its face is sharp.

    Returns
    -------
    ndarray
        float64 unit normals: (m, k, 3) for (m, k) faces, (len(indices), 3)
        for ``(indices, offsets)``. (0, 0, 0) for a corner no face
        contributes to; never NaN.

    Raises
    ------
    Error
        As `vertex_normals`; also a negative or NaN crease angle, or
        sharp_edges of the wrong size.

    Examples
    --------
    A square folded by 90 degrees along its diagonal: with a crease at 60
    degrees each triangle's corners get its own normal.

    >>> p = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [1, 1, 1.]])
    >>> vn.corner_normals(p, [[0, 1, 2], [0, 2, 3]], crease_angle=np.radians(60))[1]
    array([[ 0.70710678, -0.70710678,  0.        ],
           [ 0.70710678, -0.70710678,  0.        ],
           [ 0.70710678, -0.70710678,  0.        ]])
    """
    positions, faces = _mesh(positions, faces)
    idx, off, shape = _faces(faces)
    crease = np.pi if crease_angle is None else crease_angle
    n = library().corner_normals(_positions(positions), idx, off, method, crease, sharp_edges, threads)[0]
    return n if shape is None else n.reshape(shape + (3,))


class Plan:
    """Faces prepared once for the normals of many position sets.

    Animation, simulation and interactive editing move the vertices of a
    mesh whose faces stay the same. A plan checks and lays out the faces
    once (``vn_plan_create``); each call then only reads positions and
    writes normals: no copy of the positions, no allocation in the library.
    float32 positions on triangles take a faster path for MWE, MWA, MWSELR,
    MWAAT, MWELR and MWRELR (float arithmetic, the indices not checked
    again); float64 positions, the other schemes and polygons compute what
    `vertex_normals` does, on the plan's memory (MWA on triangles with a
    faster polynomial atan2, within 1e-9 degrees).

    Parameters
    ----------
    faces : (m, k) array_like of integers, tuple (indices, offsets), or a mesh
        As for `vertex_normals`; a mesh object gives its faces and its
        vertex count.
    vertex_count : int, optional
        The number of positions every call passes. Default: the mesh's
        vertex count, else the largest index + 1.
    threads : int, default 0
        Worker threads of every call; 0 uses one per core. Results do not
        depend on it, bit for bit.

    Raises
    ------
    Error
        Faces of the wrong shape or type, an index out of range (negative,
        or not below `vertex_count`).

    Notes
    -----
    A plan serves one call at a time: calls from several Python threads
    wait for each other. Use one plan per thread to run them side by side.
    The memory (about 4 bytes a corner, 32 a vertex and 100 a triangle)
    is freed by `close`, at the end of a ``with`` block, or when the plan
    is garbage collected.

    Examples
    --------
    >>> p = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], dtype=np.float32)
    >>> with vn.Plan([[0, 1, 2], [0, 2, 3]]) as plan:
    ...     for frame in range(3):
    ...         n = plan.normals(p * (1 + frame), "mwaat")
    >>> n[0], n.dtype
    (array([0., 0., 1.], dtype=float32), dtype('float32'))
    """

    def __init__(self, faces, vertex_count=None, *, threads=0):
        if hasattr(faces, "vertices") or hasattr(faces, "points"):  # a mesh
            positions, faces = _mesh(faces, None)
            if vertex_count is None:
                vertex_count = len(positions)
        idx, off, self._shape = _faces(faces)
        self._plan = library().plan(idx, off, vertex_count, threads)

    @property
    def vertex_count(self):
        """The number of positions each call takes."""
        return self._plan.vertex_count

    @property
    def face_count(self):
        return self._plan.face_count

    @property
    def closed(self):
        return self._plan.closed

    def close(self):
        """Frees the plan's memory; later calls raise `Error`."""
        self._plan.close()

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

    def normals(self, positions, method="mwa", *, out=None):
        """Unit normals of the vertices at these positions.

        Parameters
        ----------
        positions : (vertex_count, 3) array_like, or a mesh
            float32 and float64 arrays are read in place, rows with any byte
            stride (an interleaved vertex buffer's position columns too);
            anything else is converted once to float64.
        method : str or Method, default "mwa"
            A name from `methods` (any case), or an entry of it.
        out : (vertex_count, 3) float32 or float64 ndarray, optional
            Written in place (rows with any byte stride) and returned.

        Returns
        -------
        (vertex_count, 3) ndarray
            float32 for float32 positions, else float64 (or `out`).
            float64 positions give `vertex_normals`' results bit for bit,
            but MWA on triangles, whose corner angles come from a faster
            polynomial atan2 (within 1e-9 degrees).
            float32 positions on the fast path are computed in float
            arithmetic, within 1e-4 degrees of `vertex_normals` on the same
            positions; otherwise they are `vertex_normals`' rounded to
            float32. (0, 0, 0) where no face contributes; never NaN.

        Raises
        ------
        Error
            Positions not (vertex_count, 3), an unknown method, a closed
            plan. Nothing is written into `out` then.
        """
        return self._plan.normals(_positions(positions), method, out)[0]

    def corner_normals(self, positions, method="mwa", *, crease_angle=None, sharp_edges=None, out=None):
        """Unit normals of the corners of the faces, split at sharp edges,
        as `corner_normals` computes them.

        Parameters
        ----------
        positions, method, out
            As for `normals`; `out` has one row per corner.
        crease_angle, sharp_edges
            As for `corner_normals` (radians; one flag per corner).

        Returns
        -------
        ndarray
            (m, k, 3) for (m, k) faces, (len(indices), 3) for
            ``(indices, offsets)`` (or `out`); float32 for float32
            positions, else float64. Equal to `corner_normals`' results
            (rounded to float32 for float32 positions).
        """
        crease = np.pi if crease_angle is None else crease_angle
        given = out is not None
        n = self._plan.corner_normals(_positions(positions), method, crease, sharp_edges, out)[0]
        return n if given or self._shape is None else n.reshape(self._shape + (3,))


def weld(positions, epsilon=0.0):
    """The representative vertex of each position: welding by position.

    Two vertices are one when their positions differ by at most `epsilon`
    in every coordinate, or through a chain of such pairs. Vertices with a
    NaN coordinate are never welded.

    Parameters
    ----------
    positions : (n, 3) array_like, or a mesh (as for `vertex_normals`)
    epsilon : float, default 0.0
        In the positions' unit; 0 welds exactly equal positions (-0 == +0).

    Returns
    -------
    (n,) uint32 ndarray
        ``remap[i]``: the lowest-numbered vertex of i's group, so
        ``remap[remap] == remap``. ``remap[faces]`` are the faces on welded
        vertices.

    Raises
    ------
    Error
        A negative, NaN or infinite epsilon; positions not (n, 3).

    Examples
    --------
    >>> vn.weld([[0, 0, 0], [1, 0, 0], [0, 0, 0]])
    array([0, 1, 0], dtype=uint32)
    """
    return library().weld_positions(_positions(positions), epsilon)


def convert(src, dst=None, method="mwa", *, out_dir=None, recursive=False, overwrite=True, progress=None,
            **options):
    """Converts the mesh file `src` to `dst` with new normals, as
    ``vnconvert SRC DST --method METHOD ...`` does: the same C code, so the
    same output bytes, warnings and messages. With `out_dir`, converts a
    batch as ``vnconvert --out-dir OUT_DIR SRC...`` does.

    Parameters
    ----------
    src : str or os.PathLike, or a list of them with `out_dir`
        The formats follow the extensions (``.off``, ``.obj``, ``.ply``,
        ``.stl``, ``.gltf``, ``.glb``, ``.drc``) unless given. In a batch,
        a folder stands for its files of those formats, in name order.
    dst : str or os.PathLike
        Written atomically: on failure it is left as it was. Not given
        with `out_dir`.
    method : str or Method, default "mwa"
        A name from `methods` (any case), or an entry of it.
    out_dir : str or os.PathLike, optional
        A batch: each file of `src` goes to ``OUT_DIR/STEM.EXT`` (EXT:
        `format`'s, else the input's own), as vnconvert plans it, checked
        whole before the first file (two inputs for one output, an output
        that is its input, an option that applies to no file). Files are
        converted side by side on ``threads`` Python threads (default: one
        per core), one C thread each. A failing file is reported in the
        result; the others are still converted. A crash of the C code
        would end the process: for isolation per file, run vnconvert or
        `vn.dask`.
    recursive : bool, default False
        Batch: enter subfolders, keeping their layout under `out_dir`.
    overwrite : bool, default True
        Batch: False skips files whose output exists and is not older
        than the input (a rerun after an interruption: outputs are
        written atomically, so one that exists is whole).
    progress : None, False or callable, default None
        Batch: None draws a bar on stderr when it is a terminal; a
        callable is called as ``progress(done, total, file_result)``.
    **options
        vnconvert's flags by keyword, ``-`` spelled ``_``: ``threads=4``,
        ``crease_angle=30`` (degrees), ``weld_epsilon=1e-6``,
        ``format="glb"``, ``input_format="off"``, ``weld_scope="mesh"``,
        ``tangents="drop"``, ``draco="on"``, ``meshopt="off"``,
        ``draco_qp=11`` (also ``draco_qn``, ``draco_qt``, ``draco_qc``,
        ``draco_cl``). Switches take True: ``no_weld``, ``in_place``,
        ``apply_transforms``. Values are passed as ``str(value)`` and
        checked as vnconvert checks them; None or False leaves an option
        out. ``stats=True`` fills `Report.stats` (``vnconvert --stats``;
        one file only).

    Returns
    -------
    Report
        One file: warnings, counts (vertices, faces, triangles, welded
        vertices, hard edges, split vertices, zero normals, degenerate
        faces), timings and the formats as resolved.
    Batch
        With `out_dir`: a `FileResult` per file (converted, failed with
        vnconvert's message, or done before), and the totals
        (`Batch.summary`).

    Raises
    ------
    Error
        vnconvert's one-line message, naming the file ("in.off: cannot
        open: No such file or directory"), or the keyword vnconvert has no
        flag for. Nothing is written then. In a batch, only what refuses
        the whole batch raises.

    Examples
    --------
    >>> r = vn.convert("torus.off", "torus.glb", "mwselr", crease_angle=40)
    >>> r.triangles, r.output_format
    (1920, 'glb')
    >>> b = vn.convert(["models/"], out_dir="out", format="glb", recursive=True)
    >>> print(b.summary())  # doctest: +SKIP
    """
    io = _convert.io_library(library().path)
    if out_dir is not None:
        if dst is not None:
            raise Error("give dst (one file) or out_dir (a batch), not both")
        return _batch.run_local(io, src, out_dir, method, recursive, overwrite, progress, options)
    if dst is None:
        raise Error("convert() needs dst, the output file (or out_dir for a batch)")
    if recursive or not overwrite or progress is not None:
        raise Error("recursive, overwrite and progress are for a batch: give out_dir")
    return io.convert(src, dst, io.options(method, options))


from . import open3d  # noqa: E402 (vn.open3d.set_normals; it needs vertex_normals)
