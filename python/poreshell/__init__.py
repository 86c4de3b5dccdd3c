"""poreshell: turn a surface into a 3D-printable porous shell with round pores.

The Python binding of the poreshell C++ library. Arrays are numpy arrays; lengths are in millimetres
unless a ``units`` argument says otherwise; results are always in millimetres.

    >>> import poreshell
    >>> r = poreshell.perforate(*poreshell.load_mesh("data/stanford-bunny.obj", units="m"), alpha=2200)
    >>> r.save("bunny.stl"); r.report["mesh"]["pores_from_euler"]

Functions: perforate, estimate, prepare, load_mesh, load_points, sphere, torus, points, version.
Errors: ValueError for bad arguments (wrong shape, dtype, NaN, out-of-range option; the message names
the option in backquotes, as in `hole_diameter`), RuntimeError for other failures. Both carry
``code`` (invalid_option, invalid_input, too_large, cancelled, io, internal) and ``option`` attributes
when they come from the library.
"""

# Imported under private names, so that the package namespace holds only the API (`__all__`).
import json as _json
import os as _os

import numpy as _np

from . import _poreshell

__all__ = [
    "perforate",
    "estimate",
    "prepare",
    "Prepared",
    "load_mesh",
    "load_points",
    "sphere",
    "torus",
    "points",
    "Shape",
    "Points",
    "Result",
    "Output",
    "HOLE_DTYPE",
    "OPTION_NAMES",
    "version",
    "__version__",
]

__version__ = _poreshell.version()

#: Every option perforate() takes by keyword (the fields of the C++ poreshell::Options).
OPTION_NAMES = tuple(_poreshell.option_names())

#: The dtype of Result.holes: one row per hole through the wall, measured on the output mesh.
HOLE_DTYPE = _np.dtype(
    [
        ("centre", _np.float64, (3,)),  # mm, input frame
        ("normal", _np.float64, (3,)),  # unit surface normal
        ("diameter", _np.float64),  # mm, sqrt(4 A / pi) of the mid-wall cross-section's area A
        ("circularity", _np.float64),  # 4 pi A / P^2 (1 for a circle)
        ("nearest", _np.float64),  # mm, to the nearest other hole's centre (0 when alone)
        ("axis_ratio", _np.float64),  # minor over major axis of the cross-section (1 round)
        ("asked_diameter", _np.float64),  # mm asked at its centre (graded where asked; 0: none asked)
    ]
)

_UNITS = ("m", "cm", "mm", "inch")


def version():
    """The library's version string."""
    return _poreshell.version()


# --- Argument checks ------------------------------------------------------------------------------------


def _units(units):
    if units not in _UNITS:
        raise ValueError("`units` must be one of 'm', 'cm', 'mm', 'inch', got %r" % (units,))
    return units


def _coordinates(array, name):
    """An (n, 3) float64 C-contiguous array from anything numpy converts safely to float64."""
    try:
        a = _np.asarray(array)
    except Exception as e:  # ragged lists and the like
        raise ValueError("`%s` must be an (n, 3) array of numbers: %s" % (name, e)) from None
    if a.dtype.kind not in "iuf" or not _np.can_cast(a.dtype, _np.float64, casting="same_kind"):
        raise ValueError("`%s` must be an (n, 3) array of numbers, got dtype %s" % (name, a.dtype))
    if a.ndim != 2 or a.shape[1] != 3:
        raise ValueError("`%s` must be an (n, 3) array, got shape %s" % (name, a.shape))
    a = _np.ascontiguousarray(a, dtype=_np.float64)
    if not _np.isfinite(a).all():
        row = int(_np.argwhere(~_np.isfinite(a))[0][0])
        raise ValueError("`%s` has a NaN or infinite coordinate (row %d)" % (name, row))
    return a


def _indices(array, name, count):
    """An (m, 3) int32 C-contiguous array of indices into `count` points."""
    try:
        a = _np.asarray(array)
    except Exception as e:
        raise ValueError("`%s` must be an (m, 3) array of integers: %s" % (name, e)) from None
    if a.size == 0 and a.dtype.kind == "f":
        a = a.astype(_np.int32)  # an empty list becomes float64
    if a.dtype.kind not in "iu":
        raise ValueError("`%s` must be an (m, 3) array of integers, got dtype %s" % (name, a.dtype))
    if a.ndim != 2 or a.shape[1] != 3:
        raise ValueError("`%s` must be an (m, 3) array, got shape %s" % (name, a.shape))
    if a.size and (a.min() < 0 or a.max() >= count):
        raise ValueError(
            "`%s` has an index outside 0..%d (the vertex count is %d)" % (name, count - 1, count)
        )
    return _np.ascontiguousarray(a, dtype=_np.int32)


# --- Inputs ---------------------------------------------------------------------------------------------


class Shape:
    """One of the paper's analytic surfaces, as perforate()'s input: see sphere() and torus()."""

    def __init__(self, kind, radius=None, units="mm"):
        if kind not in ("sphere", "torus"):
            raise ValueError("unknown shape %r: use 'sphere' or 'torus'" % (kind,))
        self.kind = kind
        self.radius = radius
        self.units = _units(units)

    def _input(self):
        radius = 0.0 if self.radius is None else float(self.radius)
        if self.radius is not None and not radius > 0.0:
            raise ValueError("`radius` must be a positive length in mm, got %r" % (self.radius,))
        return _poreshell.shape_input(self.kind, radius, self.units)

    def __repr__(self):
        return "poreshell.%s(%s)" % (self.kind, "" if self.radius is None else repr(self.radius))


def sphere(radius=None, units="mm"):
    """The sphere of the paper's eq. (3.1), as an input for perforate().

    radius: the sphere's radius in mm; None: the paper's sphere in the unit cube, one unit being
    `units` ('m', 'cm', 'mm' or 'inch').
    """
    return Shape("sphere", radius, units)


def torus(major_radius=None, units="mm"):
    """The torus of the paper's section 3.2, as an input for perforate().

    major_radius: the torus's major radius in mm (the minor radius keeps the paper's ratio); None: the
    paper's torus in the unit cube, one unit being `units`.
    """
    return Shape("torus", major_radius, units)


class Points:
    """A point cloud as perforate()'s input: see points() and load_points()."""

    def __init__(self, points, patches=None, units="mm", name="points"):
        self.points = _coordinates(points, "points")
        self.patches = _indices(
            _np.zeros((0, 3), _np.int32) if patches is None else patches, "patches", len(self.points)
        )
        self.units = _units(units)
        self.name = name

    def _input(self):
        return _poreshell.points_input(self.points, self.patches, self.units, self.name)

    def __repr__(self):
        return "poreshell.Points(%d points, units=%r)" % (len(self.points), self.units)


def points(points, units="mm", patches=None):
    """A point cloud as an input for perforate().

    points: (n, 3) array of coordinates in `units` ('m', 'cm', 'mm' or 'inch').
    patches: optional (m, 3) integer array of triangles over the points (the paper's route densifies
    them; see the point_route option).
    """
    return Points(points, patches, units)


def load_mesh(path, units="mm"):
    """Reads a triangle mesh (STL, OBJ, PLY, OFF or 3MF, by extension).

    units: the unit of the file's coordinates ('m', 'cm', 'mm' or 'inch').
    Returns (vertices, faces): vertices an (n, 3) float64 array in millimetres (the file's coordinates
    times the unit's length in mm), faces an (m, 3) int32 array of vertex indices, counter-clockwise
    seen from outside. Duplicate vertices are welded.
    """
    return _poreshell.load_mesh(_os.fspath(path), _units(units))


def load_points(path, units="mm"):
    """Reads a point cloud (XYZ text: .xyz, .txt, .pts; or PLY vertices) as a Points input.

    units: the unit of the file's coordinates; the Points keep them in that unit.
    """
    pts, patches = _poreshell.load_points(_os.fspath(path))
    p = Points(pts, patches, units, name=_os.fspath(path))
    return p


# --- Results --------------------------------------------------------------------------------------------


def _holes_array(holes):
    out = _np.zeros(len(holes["diameter"]), dtype=HOLE_DTYPE)
    for field in HOLE_DTYPE.names:
        out[field] = holes[field]
    return out


class Output:
    """The solid at one pore level.

    iso: the pore level; vertices: (n, 3) float64 in mm (the input's frame); faces: (m, 3) int32,
    counter-clockwise seen from outside (closed, manifold, oriented); holes: structured array of
    HOLE_DTYPE (fields centre (n, 3) mm, normal (n, 3), diameter mm, circularity, nearest mm,
    axis_ratio). A preview (preview=True) is the input surface itself, not a closed shell, and
    pattern is its order parameter per vertex, (n,) float64: a hole where pattern > iso (else None).
    """

    def __init__(self, level, run=None, index=0):
        self._run = run  # the C++ side the viewer page needs (none for an Output made by hand)
        self._index = index
        self.iso = float(level["iso"])
        self.vertices = level["vertices"]
        self.faces = level["faces"]
        self.holes = _holes_array(level["holes"])
        self.pattern = level.get("pattern")

    def save(self, path):
        """Writes this mesh in mm: .stl (binary), .3mf, .obj or .ply (binary) by extension; a
        preview's .ply has its holes as vertex colours, as the CLI writes it. .html writes the
        interactive viewer page (the CLI's --html) and .png its picture (the CLI's --png, which needs
        Chromium).

        The file is written to a temporary name and renamed, so a failure leaves no partial file.
        """
        path = _os.fspath(path)
        extension = _os.path.splitext(path)[1].lower()
        if extension not in (".html", ".png"):
            _poreshell.save_mesh(path, self.vertices, self.faces, self.iso, self.pattern)
            return
        if self._run is None:
            raise ValueError("only an Output of a perforate() Result can be saved as %s" % (extension,))
        if extension == ".html":
            _poreshell.save_view(self._run, self._index, self.vertices, self.faces, path, "")
            return
        # A picture is taken of a page in a temporary file beside it, as the CLI does.
        page = _os.path.splitext(path)[0] + ".tmp-view%d.html" % _os.getpid()
        try:
            _poreshell.save_view(self._run, self._index, self.vertices, self.faces, page, path)
        finally:
            if _os.path.exists(page):
                _os.remove(page)

    def __repr__(self):
        return "poreshell.Output(iso=%g, %d vertices, %d faces, %d holes)" % (
            self.iso,
            len(self.vertices),
            len(self.faces),
            len(self.holes),
        )


class Result:
    """What perforate() returns.

    outputs: one Output per pore level (the `iso` option's levels, or the hole map's level).
    vertices, faces, holes, iso: those of the first output (see Output).
    report: the JSON report's content as a dict (README.md lists its fields; e.g.
    report["mesh"]["triangles"], report["mesh"]["pores_from_euler"], report["pattern"]["spots"]).
    """

    def __init__(self, levels, report_text, run=None):
        self.outputs = [Output(level, run, i) for i, level in enumerate(levels)]
        self.report = _json.loads(report_text)

    @property
    def vertices(self):
        return self.outputs[0].vertices

    @property
    def faces(self):
        return self.outputs[0].faces

    @property
    def holes(self):
        return self.outputs[0].holes

    @property
    def iso(self):
        return self.outputs[0].iso

    def save(self, path):
        """Writes the first output (see Output.save: a mesh by its extension, or .html the viewer page,
        .png its picture); use outputs[i].save for the other levels."""
        self.outputs[0].save(path)

    def save_report(self, path):
        """Writes the JSON report (indented), to a temporary name first and then renamed."""
        path = _os.fspath(path)
        _poreshell.check_output_path(path)
        tmp = "%s.tmp%d" % (path, _os.getpid())
        try:
            with open(tmp, "w", encoding="utf-8") as f:
                _json.dump(self.report, f, indent=2)
                f.write("\n")
            _os.replace(tmp, path)
        except BaseException:
            if _os.path.exists(tmp):
                _os.remove(tmp)
            raise

    def __repr__(self):
        return "poreshell.Result(%s)" % ", ".join(repr(o) for o in self.outputs)


# --- The run --------------------------------------------------------------------------------------------


def perforate(
    vertices,
    faces=None,
    *,
    units=None,
    hole_diameter=None,
    spacing=None,
    porosity=None,
    wall=None,
    offset="centered",
    rim=None,
    keep_out=(),
    keep_out_boxes=(),
    grade=None,
    mode="shell",
    seed=1,
    threads=0,
    progress=None,
    max_seconds=0,
    vertex_fields=None,
    **model,
):
    """Perforates a surface: round pores in a printable shell. Returns a Result (meshes in mm).

    The input, first argument(s), one of:
      vertices, faces   an (n, 3) array of coordinates in `units` (float64, or anything numpy casts
                        to it safely; no NaN) and an (m, 3) integer array of vertex indices
                        (counter-clockwise seen from outside); open surfaces and scans with holes are fine
      path              a mesh file (str or os.PathLike; STL, OBJ, PLY, OFF, 3MF), coordinates in `units`
      Shape             poreshell.sphere(radius_mm) or poreshell.torus(major_radius_mm)
      Points            poreshell.points(array, units=...) or poreshell.load_points(path, units=...)
      mesh object       anything with `.vertices` and `.faces` arrays (a trimesh.Trimesh, a Result)

    units: 'm', 'cm', 'mm' or 'inch': the unit of vertices or the file (default 'mm'); Shape and Points
        carry their own (giving a different one here is an error).

    Holes, in mm (with hole_diameter the hole map chooses alpha, epsilon_m, phi_bar, dt_h, iso and the
    voxel size, which may then not be given):
      hole_diameter  hole diameter in mm
      spacing        centre to nearest centre in mm (default hole_diameter / 0.6)
      porosity       open share of the surface (0..1), instead of one of the two lengths
      grade          hole-size grading: the CLI's spec string ('axis:z:4:8', 'line:X,Y,Z:D1:X,Y,Z:D2',
                     'radial:X,Y,Z:R:D0', 'field:NAME[:D0:D1]') or a dict with keys kind ('axis', 'line',
                     'radial', 'field'), axis (0-2 or 'x'/'y'/'z'), from, to (3-tuples, mm),
                     from_diameter, to_diameter, radius (mm), field, mapped

    The printed solid:
      mode           'shell' (a wall, pores straight through it) or 'narrow_volume' (the paper's Fig. 3b)
      wall           wall thickness in mm (default: 2 mm with hole_diameter, else the band's width, 3.81 voxels)
      offset         'centered', 'inside' or 'outside' the surface
      rim            mm of solid along the mesh's open boundary (default: half a hole with hole_diameter,
                     so that no hole is cut open by the outline, else none; 0 allows notches)
      keep_out       sequence of (x, y, z, r) solid spheres in mm (in the input's frame, scaled to mm)
      keep_out_boxes sequence of (x0, y0, z0, x1, y1, z1) solid boxes in mm (two opposite corners)
      vertex_fields  dict name -> (n,) array of per-vertex scalars of the mesh input, for the
                     keep_out_mask option and grading by a field (with a path: names of PLY properties,
                     as a sequence of str)

    The run:
      seed           seed of the initial random field (same seed, same result)
      threads        worker threads, 0: all cores (results do not depend on it)
      progress       callable(stage, fraction): stage is 'input', 'band', 'solve', 'shell', 'mesh' or
                     'holes', in that order (a preview: no 'shell' or 'holes'), fraction 0..1 of that
                     stage; called from the run's threads with the GIL held, at each stage's start
                     and a few times a second while solving. An exception it raises cancels the run
                     and propagates out of perforate() unchanged.
      max_seconds    a time budget: a run still computing after it raises RuntimeError (code
                     'out_of_time'); 0: none

    **model: the other options by their API names (OPTION_NAMES lists them all):
      resolution (131: grid points along the longest side), voxel_size (mm, instead), alpha (1400),
      epsilon_m (4), dt_h (100), phi_bar (-0.3), iso (0, or a sequence of levels: one output each),
      initial_amplitude (0.5), tolerance (1e-3), max_steps (2000), stop ('auto', 'paper' or 'holes'),
      layout ('auto', 'paper' or 'cvt': docs/solver.md "Layout"), solver ('fast' or 'reference'),
      fast_tolerance, min_stabilisation, coarse_start (bool), inner ('gauss_seidel' or 'jacobi'),
      inner_tolerance, energy_every, point_route ('direct' or 'paper'), keep_out_mask (a vertex
      field's name), max_triangles, max_deviation (mm), lean (bool: fewer triangles within max_deviation
      for several times the reduction's time), max_memory_gb, preview (bool: the pattern alone,
      painted on the input surface, in about a second; Output.pattern), scale (multiplies the input),
      thin_feature_ratio and crease_angle (parts kept solid), keep_fragments, min_part_fraction.
      An unknown keyword raises TypeError.

    The GIL is released while the run works; Ctrl-C (KeyboardInterrupt) cancels it within about half a
    second. Raises ValueError for bad arguments (the message names the option in backquotes) and
    RuntimeError for other failures (too large for memory, internal errors); library errors carry
    `code` and `option` attributes.

    Example: the bundled Stanford bunny (coordinates in metres) with the paper's section 3.4 alpha:
        r = poreshell.perforate("data/stanford-bunny.obj", units="m", alpha=2200)
        r.save("bunny.stl"); print(r.report["mesh"]["pores_from_euler"], len(r.faces))
    """
    options = dict(
        hole_diameter=hole_diameter,
        spacing=spacing,
        porosity=porosity,
        wall=wall,
        offset=offset,
        rim=rim,
        keep_out=keep_out,
        keep_out_boxes=keep_out_boxes,
        grade=grade,
        mode=mode,
        seed=seed,
        threads=threads,
    )
    for name, value in model.items():
        if name not in OPTION_NAMES or name in options:
            raise TypeError("perforate() got an unexpected keyword argument %r" % (name,))
        options[name] = value
    if progress is not None and not callable(progress):
        raise ValueError("`progress` must be a callable (stage, fraction) or None")
    if not max_seconds >= 0:
        raise ValueError("`max_seconds` must be a number of seconds >= 0 (0: no budget)")
    return Result(
        *_poreshell.perforate(
            _make_input(vertices, faces, units, vertex_fields), options, progress, float(max_seconds)
        )
    )


def estimate(vertices, faces=None, *, units=None, vertex_fields=None, **options):
    """What perforate() with the same input and options will cost, before running it.

    Takes perforate()'s input and options (not `progress` or `max_seconds`) and returns a dict:
      size_mm        the model's bounding box in mm, (x, y, z)
      grid           the grid's points along x, y, z; voxel_size_mm its spacing in mm
      band_voxels    the narrow band's voxels (a preview of a mesh: its surface layer)
      seconds        the run's wall time on 2 cores of the calibration machine (docs/benchmarks.md
                     "Estimates": expect +-30%, more under load)
      peak_bytes     the run's peak resident memory
      triangles      per output level; stl_bytes its size as binary STL
      preview        whether the options ask for a preview; ply_bytes its output as PLY (else 0)
      warnings       list of str: a model under 5 mm or over 3 m across (with the `units` that would
                     make it 20-500 mm), holes over a third of its smallest extent, a run over 5
                     minutes or an output over 300 MB

    It places the input as the run would (a tenth of a second for a 70k-triangle scan) and counts the
    band on a coarser grid. Raises as perforate() does for bad input and options.

    Example: r = poreshell.estimate("scan.stl", hole_diameter=8, spacing=12); print(r["seconds"])
    """
    return _poreshell.estimate(_make_input(vertices, faces, units, vertex_fields), options)


class Prepared:
    """An input placed on its grid with its options, once: estimate() and perforate() start from it.

    Made by poreshell.prepare(). Placing a large scan (its search structures) takes seconds; a caller
    that estimates before it runs saves doing it twice. The answers are those of poreshell.estimate()
    and poreshell.perforate() with the same input and options.
    """

    def __init__(self, prepared):
        self._prepared = prepared

    def estimate(self):
        """poreshell.estimate()'s dict for the prepared input and options."""
        return _poreshell.estimate_prepared(self._prepared)

    def perforate(self, progress=None, max_seconds=0):
        """poreshell.perforate() of the prepared input and options: a Result. `progress` and
        `max_seconds` as there."""
        if progress is not None and not callable(progress):
            raise ValueError("`progress` must be a callable (stage, fraction) or None")
        if not max_seconds >= 0:
            raise ValueError("`max_seconds` must be a number of seconds >= 0 (0: no budget)")
        return Result(*_poreshell.perforate_prepared(self._prepared, progress, float(max_seconds)))

    def __repr__(self):
        return "<poreshell.Prepared>"


def prepare(vertices, faces=None, *, units=None, vertex_fields=None, **options):
    """Checks the options and places the input once, for estimate() and perforate() after it.

    Takes perforate()'s input and options (not `progress` or `max_seconds`, which its perforate()
    takes) and returns a Prepared. Raises as perforate() does for bad input and options.

    Example:
        p = poreshell.prepare("scan.stl", hole_diameter=8, spacing=12)
        if p.estimate()["seconds"] < 60:
            p.perforate().save("part.3mf")
    """
    return Prepared(_poreshell.prepare(_make_input(vertices, faces, units, vertex_fields), options))


def _make_input(first, faces, units, vertex_fields):
    if isinstance(first, (Shape, Points)):
        if faces is not None:
            raise ValueError("`faces` is only for a vertex array; a %s has none" % type(first).__name__)
        if vertex_fields:
            raise ValueError("`vertex_fields` is only for a mesh input")
        if units is not None and units != first.units:
            raise ValueError(
                "`units` %r differs from the input's own %r: give units to %s instead"
                % (units, first.units, "points()" if isinstance(first, Points) else "the shape")
            )
        return first._input()
    units = _units("mm" if units is None else units)
    if faces is None and hasattr(first, "vertices") and hasattr(first, "faces"):
        first, faces = first.vertices, first.faces  # a trimesh.Trimesh, a Result
    if isinstance(first, (str, _os.PathLike)):
        if faces is not None:
            raise ValueError("`faces` is only for a vertex array, not a file")
        fields = [] if vertex_fields is None else list(vertex_fields)
        if not all(isinstance(f, str) for f in fields):
            raise ValueError("with a file, `vertex_fields` names PLY vertex properties (a sequence of str)")
        return _poreshell.file_mesh_input(_os.fspath(first), units, fields)
    if faces is None:
        raise ValueError(
            "perforate() needs vertices and faces, a mesh file's path, a mesh object with `.vertices` "
            "and `.faces`, a Shape (poreshell.sphere, poreshell.torus) or Points (poreshell.points)"
        )
    v = _coordinates(first, "vertices")
    f = _indices(faces, "faces", len(v))
    fields = {}
    for name, values in (vertex_fields or {}).items():
        a = _np.asarray(values)
        if a.dtype.kind not in "iufb" or a.shape != (len(v),):
            raise ValueError(
                "vertex field %r must be a (%d,) array of numbers, got shape %s dtype %s"
                % (name, len(v), a.shape, a.dtype)
            )
        fields[str(name)] = a.astype(_np.float64).tolist()
    return _poreshell.mesh_input(v, f, units, "mesh", fields)
