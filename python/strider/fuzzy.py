"""Fuzzy engines evaluated over whole NumPy arrays by strider's compiled inference.

>>> from strider.fuzzy import Engine
>>> engine = Engine.from_fll(open("ObstacleAvoidance.fll").read())   # doctest: +SKIP
>>> engine.process({"obstacle": np.linspace(0, 1, 100_000)})["mSteer"]  # doctest: +SKIP
"""

from __future__ import annotations

import numbers
import os
from typing import Dict, Mapping, Optional, Union

import numpy as np

from . import _strider
from ._strider import StriderError

__all__ = ["Engine", "StriderError"]

ArrayLike = Union[float, "np.typing.ArrayLike"]


class Engine:
    """A fuzzy engine (FuzzyLite Language), or the engines a Rhai script builds layered into one
    network (outputs feed later inputs of the same name), as ``strider fuzzy eval`` runs it."""

    __slots__ = ("_native",)

    def __init__(self, native: "_strider.Engine") -> None:
        self._native = native

    @classmethod
    def from_fll(cls, text: str, *, file: str = "<fll>") -> "Engine":
        """An engine from FLL text; errors name ``file``, line and column."""
        if not isinstance(text, str):
            raise TypeError(f"from_fll expects the FLL text as a str, found {type(text).__name__}")
        return cls(_strider.Engine.from_fll(text, file))

    @classmethod
    def from_rhai(cls, path: Union[str, "os.PathLike[str]"], *, engine: Optional[str] = None) -> "Engine":
        """The engines a Rhai script (or an ``.fll`` file) at ``path`` builds, layered;
        ``engine`` keeps only the one of that name."""
        return cls(_strider.Engine.from_rhai(os.fspath(path), engine))

    @property
    def inputs(self) -> list:
        """The input variables' names."""
        return self._native.inputs

    @property
    def outputs(self) -> list:
        """The output variables' names."""
        return self._native.outputs

    def to_fll(self) -> str:
        """The engine as FLL text (a single engine only)."""
        return self._native.to_fll()

    def process(self, inputs: Mapping[str, ArrayLike]) -> Dict[str, np.ndarray]:
        """Evaluate the engine on every element of the input arrays.

        ``inputs`` maps each input variable's name to a number or an array; arrays broadcast
        together (NumPy rules). Returns each output's values as a float64 array of the
        broadcast shape. Rows are evaluated in order (an output that keeps its previous value
        when no rule fires sees the row before), over all cores when rows are independent.

        Raises:
            StriderError: an input is missing or not an input of the engine, or the arrays do
                not broadcast.
            TypeError: an input is not a number or an array of numbers (``None``, a string, a
                complex number), anywhere in it.
        """
        if not isinstance(inputs, Mapping):
            raise TypeError(f"process expects a dict of input arrays, found {type(inputs).__name__}")
        names = self.inputs
        unknown = [k for k in inputs if k not in names]
        if unknown:
            raise StriderError(f"{unknown[0]!r} is not an input of this engine (inputs: {', '.join(names)})")
        missing = [n for n in names if n not in inputs]
        if missing:
            raise StriderError(f"input {missing[0]!r} is missing (inputs: {', '.join(names)})")
        arrays = [_numbers(n, inputs[n]) for n in names]
        try:
            shaped = np.broadcast_arrays(*arrays) if arrays else []
        except ValueError as e:
            raise StriderError(f"the input arrays do not broadcast together: {e}") from None
        shape = shaped[0].shape if shaped else ()
        columns = [np.ascontiguousarray(a, dtype=np.float64).reshape(-1) for a in shaped]
        outs = self._native._process(columns)
        return {name: col.reshape(shape) for name, col in zip(self.outputs, outs)}

    def __repr__(self) -> str:
        return repr(self._native)


def _numbers(name: str, value: ArrayLike) -> np.ndarray:
    """``value`` as a float64 array, or a ``TypeError`` naming input ``name`` when it holds
    anything but real numbers (NumPy alone would turn ``None`` into NaN and ``"1.5"`` into 1.5)."""
    wanted = f"input {name!r} must be a number or an array of numbers"
    try:
        array = np.asarray(value)
    except (TypeError, ValueError) as e:
        raise TypeError(f"{wanted}: {e}") from None
    if array.dtype.kind == "O":
        bad = [x for x in array.flat if not isinstance(x, numbers.Real)]
        if bad:
            raise TypeError(f"{wanted}, found {type(bad[0]).__name__}")
    elif array.dtype.kind not in "biuf":
        raise TypeError(f"{wanted}, found an array of {array.dtype}")
    return array.astype(np.float64)
