# Type stubs of the poreshell package (PEP 561: py.typed beside it). The docstrings in __init__.py are
# the documentation; these give the types only.

import os
from typing import Any, Callable, Dict, List, Mapping, Optional, Protocol, Sequence, Tuple, Union

import numpy as np
import numpy.typing as npt

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

__version__: str
OPTION_NAMES: Tuple[str, ...]
HOLE_DTYPE: np.dtype[Any]

_Path = Union[str, "os.PathLike[str]"]
_Units = str  # 'm', 'cm', 'mm' or 'inch'
_Progress = Callable[[str, float], object]

class _MeshLike(Protocol):
    """A trimesh.Trimesh or anything with (n, 3) `vertices` and (m, 3) integer `faces`."""

    @property
    def vertices(self) -> npt.ArrayLike: ...
    @property
    def faces(self) -> npt.ArrayLike: ...

def version() -> str: ...

class Shape:
    kind: str
    radius: Optional[float]
    units: _Units
    def __init__(self, kind: str, radius: Optional[float] = ..., units: _Units = ...) -> None: ...

def sphere(radius: Optional[float] = ..., units: _Units = ...) -> Shape: ...
def torus(major_radius: Optional[float] = ..., units: _Units = ...) -> Shape: ...

class Points:
    points: npt.NDArray[np.float64]
    patches: npt.NDArray[np.int32]
    units: _Units
    name: str
    def __init__(
        self, points: npt.ArrayLike, patches: Optional[npt.ArrayLike] = ..., units: _Units = ..., name: str = ...
    ) -> None: ...

def points(points: npt.ArrayLike, units: _Units = ..., patches: Optional[npt.ArrayLike] = ...) -> Points: ...
def load_mesh(path: _Path, units: _Units = ...) -> Tuple[npt.NDArray[np.float64], npt.NDArray[np.int32]]: ...
def load_points(path: _Path, units: _Units = ...) -> Points: ...

class Output:
    iso: float
    vertices: npt.NDArray[np.float64]
    faces: npt.NDArray[np.int32]
    holes: npt.NDArray[np.void]
    pattern: Optional[npt.NDArray[np.float64]]
    def __init__(self, level: Mapping[str, Any], run: Any = ..., index: int = ...) -> None: ...
    def save(self, path: _Path) -> None: ...

class Result:
    outputs: List[Output]
    report: Dict[str, Any]
    def __init__(self, levels: Sequence[Mapping[str, Any]], report_text: str, run: Any = ...) -> None: ...
    @property
    def vertices(self) -> npt.NDArray[np.float64]: ...
    @property
    def faces(self) -> npt.NDArray[np.int32]: ...
    @property
    def holes(self) -> npt.NDArray[np.void]: ...
    @property
    def iso(self) -> float: ...
    def save(self, path: _Path) -> None: ...
    def save_report(self, path: _Path) -> None: ...

_Input = Union[npt.ArrayLike, _Path, Shape, Points, _MeshLike]

def perforate(
    vertices: _Input,
    faces: Optional[npt.ArrayLike] = ...,
    *,
    units: Optional[_Units] = ...,
    hole_diameter: Optional[float] = ...,
    spacing: Optional[float] = ...,
    porosity: Optional[float] = ...,
    wall: Optional[float] = ...,
    offset: str = ...,
    rim: Optional[float] = ...,
    keep_out: Sequence[Sequence[float]] = ...,
    keep_out_boxes: Sequence[Sequence[float]] = ...,
    grade: Union[None, str, Mapping[str, Any]] = ...,
    mode: str = ...,
    seed: int = ...,
    threads: int = ...,
    progress: Optional[_Progress] = ...,
    max_seconds: float = ...,
    vertex_fields: Union[None, Mapping[str, npt.ArrayLike], Sequence[str]] = ...,
    **model: Any,
) -> Result: ...
def estimate(
    vertices: _Input,
    faces: Optional[npt.ArrayLike] = ...,
    *,
    units: Optional[_Units] = ...,
    vertex_fields: Union[None, Mapping[str, npt.ArrayLike], Sequence[str]] = ...,
    **options: Any,
) -> Dict[str, Any]: ...

class Prepared:
    def __init__(self, prepared: Any) -> None: ...
    def estimate(self) -> Dict[str, Any]: ...
    def perforate(self, progress: Optional[_Progress] = ..., max_seconds: float = ...) -> Result: ...

def prepare(
    vertices: _Input,
    faces: Optional[npt.ArrayLike] = ...,
    *,
    units: Optional[_Units] = ...,
    vertex_fields: Union[None, Mapping[str, npt.ArrayLike], Sequence[str]] = ...,
    **options: Any,
) -> Prepared: ...
