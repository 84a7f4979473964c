"""Type stubs of the extension module brittle_dem._native (python/src/lib.rs). SI units."""

from os import PathLike
from typing import Any, Callable, Dict, List, Optional, Tuple, Union

import numpy as np
import numpy.typing as npt

_Path = Union[str, PathLike[str]]
_Length = Union[float, str]  # m, or a string with unit: "0.5mm", "20um", "1e-3m"
_Fraction = Union[float, str]  # a fraction of the grain's R_eq, or a length with unit

def version() -> str: ...

class Template:
    """A clump template: discs standing for one grain (lengths m, mass kg, inertia kg m^2)."""
    @staticmethod
    def load(path: _Path) -> Template: ...
    def save(self, path: _Path) -> None: ...
    def to_json(self) -> str: ...
    def to_dict(self) -> Dict[str, Any]: ...
    @property
    def id(self) -> str: ...
    @property
    def method(self) -> str: ...
    @property
    def density(self) -> float:
        """kg/m^3"""
    @property
    def thickness(self) -> float:
        """m"""
    @property
    def mass(self) -> float:
        """kg"""
    @property
    def centroid(self) -> npt.NDArray[np.float64]:
        """m, shape (2,), in the grain's frame"""
    @property
    def inertia(self) -> float:
        """kg m^2 about the grain centroid"""
    @property
    def inertia_own(self) -> float:
        """kg m^2 about the clump's own mass centre"""
    @property
    def target(self) -> Dict[str, Any]: ...
    @property
    def discs(self) -> npt.NDArray[np.float64]:
        """shape (k, 4): x, y, r (m), m (kg)"""
    @property
    def n_discs(self) -> int: ...
    @property
    def cover(self) -> float:
        """area cover A_r in [0, 1]"""
    @property
    def area(self) -> float:
        """grain area, m^2"""

def template_from_points(
    points: npt.NDArray[np.float64],
    *,
    name: str = "grain",
    units: str = "m",
    method: str = "improved",
    cover: float = 0.95,
    r_min: Optional[_Fraction] = None,
    r_max: Optional[_Fraction] = None,
    max_discs: int = 64,
    density: float = 2650.0,
    thickness: float = 1.0,
    resample: Optional[int] = None,
    spacing: Optional[_Fraction] = None,
    node_radius: float = 1.0,
) -> Template: ...
def template_from_file(
    path: _Path,
    *,
    units: Optional[str] = None,
    method: str = "improved",
    cover: float = 0.95,
    r_min: Optional[_Fraction] = None,
    r_max: Optional[_Fraction] = None,
    max_discs: int = 64,
    density: float = 2650.0,
    thickness: float = 1.0,
    resample: Optional[int] = None,
    spacing: Optional[_Fraction] = None,
    node_radius: float = 1.0,
) -> Template: ...
def read_outline(
    path: _Path, *, units: Optional[str] = None
) -> Tuple[npt.NDArray[np.float64], npt.NDArray[np.float64]]: ...

class LabModel:
    """A material model (density kg/m^3, thickness m, r_mean m, micro-parameters Pa)."""
    @staticmethod
    def load(path: _Path) -> LabModel: ...
    @staticmethod
    def from_dict(d: Dict[str, Any]) -> LabModel: ...
    def to_dict(self) -> Dict[str, Any]: ...
    @property
    def density(self) -> float: ...
    @property
    def r_mean(self) -> float: ...
    def with_r_mean(self, r_mean: float) -> LabModel: ...

class SpecimenParams:
    """Specimen parameters (lengths m, stresses Pa, density kg/m^3)."""
    def __init__(
        self,
        method: str,
        width: _Length,
        height: _Length,
        r_min: _Length,
        r_max: _Length,
        density: float,
        youngs: float,
        tensile: float,
        seed: int = 1,
        overrides: Optional[Dict[str, Any]] = None,
    ) -> None: ...
    @staticmethod
    def from_model(
        model: LabModel,
        width: _Length,
        height: _Length,
        r_min: _Length,
        r_max: _Length,
        method: str = "traditional",
        seed: int = 1,
        overrides: Optional[Dict[str, Any]] = None,
    ) -> SpecimenParams: ...
    @staticmethod
    def from_dict(d: Dict[str, Any]) -> SpecimenParams: ...
    def to_dict(self) -> Dict[str, Any]: ...
    @property
    def method(self) -> str: ...
    @property
    def width(self) -> float: ...
    @property
    def height(self) -> float: ...
    @property
    def r_min(self) -> float: ...
    @property
    def r_max(self) -> float: ...
    @property
    def seed(self) -> int: ...

class Specimen:
    """A generated specimen."""
    @property
    def summary(self) -> Dict[str, Any]: ...
    def summary_text(self) -> str: ...
    @property
    def params(self) -> SpecimenParams: ...
    @property
    def n_discs(self) -> int: ...
    @property
    def n_bonds(self) -> int: ...
    def discs(self) -> Dict[str, npt.NDArray[Any]]:
        """x, y, r, theta (m, rad), vx, vy, omega (m/s, rad/s), m (kg): float64; id, group: uint32"""
    def save(self, path: _Path, material: Optional[str] = None) -> None: ...

def generate_specimen(
    params: SpecimenParams,
    *,
    threads: Optional[int] = None,
    callback: Optional[Callable[[str, float], Optional[bool]]] = None,
) -> Specimen: ...

class CuttingTest:
    """A checked cutting test (depth, length m; speed m/s; angles rad)."""
    @staticmethod
    def from_json(text: str) -> CuttingTest: ...
    def to_dict(self) -> Dict[str, Any]: ...
    @property
    def depth(self) -> float: ...
    @property
    def speed(self) -> float: ...
    @property
    def length(self) -> float: ...

class CuttingResult:
    """cutting.result.json (forces N for the disc thickness)."""
    def to_dict(self) -> Dict[str, Any]: ...
    def report(self) -> str: ...
    @property
    def out_dir(self) -> str: ...
    @property
    def main_force_mean(self) -> float: ...
    @property
    def main_force_peak(self) -> float: ...
    @property
    def vertical_force_mean(self) -> float: ...
    @property
    def vertical_force_peak(self) -> float: ...
    @property
    def discs(self) -> int: ...
    @property
    def steps(self) -> int: ...
    @property
    def wall_time_s(self) -> float: ...
    @property
    def window(self) -> Tuple[float, float]: ...

def cut(
    out: _Path,
    test: CuttingTest,
    *,
    specimen: Optional[SpecimenParams] = None,
    specimen_file: Optional[_Path] = None,
    model: Optional[LabModel] = None,
    threads: Optional[int] = None,
    callback: Optional[Callable[[int, int], Optional[bool]]] = None,
    every: int = 0,
    checkpoints: int = 20,
    resume: bool = True,
) -> CuttingResult: ...

class LabResult:
    """A quasi-static lab test's <name>.result.json."""
    def to_dict(self) -> Dict[str, Any]: ...
    @property
    def result(self) -> Dict[str, Any]: ...
    @property
    def name(self) -> str: ...
    @property
    def run_dir(self) -> str: ...
    @property
    def out_dir(self) -> str: ...

def lab_test(
    kind: str,
    out: _Path,
    specimen: SpecimenParams,
    *,
    test: Optional[Dict[str, Any]] = None,
    model: Optional[LabModel] = None,
    threads: Optional[int] = None,
    callback: Optional[Callable[[int, int], Optional[bool]]] = None,
    every: int = 0,
) -> LabResult: ...

class RunResult:
    @property
    def ending(self) -> str: ...
    @property
    def summary(self) -> Dict[str, Any]: ...
    @property
    def out_dir(self) -> str: ...
    @property
    def steps(self) -> int: ...

def run_scene(
    scene_json: str,
    scene_file: _Path,
    *,
    out: Optional[_Path] = None,
    max_steps: Optional[int] = None,
    threads: Optional[int] = None,
    callback: Optional[Callable[[Dict[str, Any]], Optional[bool]]] = None,
    every: int = 0,
    restart: Optional[_Path] = None,
) -> RunResult: ...
def render(
    input: _Path,
    out: _Path,
    *,
    width: int = 1200,
    color: str = "grain",
    bonds: bool = False,
    broken: bool = False,
    view: Optional[List[float]] = None,
    speed_max: Optional[float] = None,
    outline: Optional[_Path] = None,
) -> Dict[str, Any]: ...
def render_png(
    input: _Path,
    *,
    width: int = 1200,
    color: str = "grain",
    bonds: bool = False,
    broken: bool = False,
    view: Optional[List[float]] = None,
    speed_max: Optional[float] = None,
    outline: Optional[_Path] = None,
) -> bytes: ...
def sweep_table(dir: _Path, *, timing: bool = True) -> Dict[str, Any]: ...
def sweep_status(dir: _Path) -> List[str]: ...
