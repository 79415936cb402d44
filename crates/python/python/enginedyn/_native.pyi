"""Type stubs of the binding to enginedyn's Rust session layer."""

import os
from typing import Dict, List, Optional, Sequence, Tuple, Union, final

import numpy as np
import numpy.typing as npt

__version__: str
__all__ = [
    "EnginedynError",
    "DiagramError",
    "EngineFileError",
    "UsageError",
    "Engine",
    "NativeSession",
    "Run",
    "BatchRow",
    "check_reader",
    "check_method",
    "canonical",
    "speeds",
    "__version__",
]

class EnginedynError(Exception): ...

class DiagramError(EnginedynError):
    path: Optional[str]
    line: Optional[int]
    column: Optional[int]

class EngineFileError(EnginedynError):
    path: Optional[str]
    key: Optional[str]

class UsageError(EnginedynError): ...

@final
class Engine:
    @staticmethod
    def from_toml(path: Union[str, os.PathLike[str]]) -> Engine: ...
    @staticmethod
    def from_str(text: str, path: Optional[Union[str, os.PathLike[str]]] = None) -> Engine: ...
    @staticmethod
    def bundled(name: str) -> Engine: ...
    @staticmethod
    def bundled_names() -> List[str]: ...
    @property
    def name(self) -> str: ...
    @property
    def cylinders(self) -> int: ...
    @property
    def text(self) -> str: ...
    @property
    def path(self) -> Optional[str]: ...
    @property
    def bundled_name(self) -> Optional[str]: ...
    @property
    def diagram(self) -> Optional[str]: ...

@final
class BatchRow:
    @property
    def file(self) -> str: ...
    @property
    def error(self) -> Optional[str]: ...
    @property
    def summary(self) -> Optional[str]: ...
    @property
    def notes(self) -> List[str]: ...

@final
class Run:
    def summary_json(self) -> str: ...
    @property
    def notes(self) -> List[str]: ...
    def curves(self, centered: bool = False) -> Dict[str, npt.NDArray[np.float64]]: ...
    def harmonics(self) -> Dict[str, npt.NDArray[np.float64]]: ...
    def charts(self) -> List[str]: ...
    def svg(self, name: str) -> str: ...
    def files(self, centered: bool = False) -> List[Tuple[str, bytes]]: ...

@final
class NativeSession:
    def __new__(
        cls,
        engine: Engine,
        method_options: Dict[str, object],
        reader_options: Dict[str, object],
        full: bool = True,
    ) -> NativeSession: ...
    def analyse(self, paths: Sequence[Union[str, os.PathLike[str]]]) -> Run: ...
    def analyse_torque(self, path: Union[str, os.PathLike[str]]) -> Run: ...
    def analyse_columns(
        self,
        names: Sequence[str],
        columns: Sequence[npt.NDArray[np.float64]],
        rpm: Optional[float] = None,
    ) -> Run: ...
    def torsion(
        self,
        rpms: Optional[Sequence[float]] = None,
        path: Optional[Union[str, os.PathLike[str]]] = None,
    ) -> Tuple[str, str, str, List[str], List[Tuple[str, str]]]: ...
    def batch(self, paths: Sequence[Union[str, os.PathLike[str]]], jobs: int = 0) -> List[BatchRow]: ...

def check_reader(options: Dict[str, object]) -> None: ...
def check_method(options: Dict[str, object]) -> None: ...
def speeds(start: float, stop: float, step: float) -> List[float]: ...
def canonical(name: str) -> Optional[Tuple[str, float]]: ...
