"""strider from Python: navigation runs, simulations, fuzzy engines, Gymnasium environments
(``import strider.gym``) and Ray batches (``strider.ray``).

Everything goes through strider's own Rust library, so ``strider.run`` returns exactly what
``strider run --format json`` prints, and a :class:`Simulation` steps exactly what that run
steps. Bad input raises :class:`StriderError` (a ``ValueError``) with strider's
``file:line:col`` message; long calls release the GIL and stop on Ctrl-C.
"""

from __future__ import annotations

import json
import os
from typing import Any, Iterable, Optional, Tuple, Union

from . import fuzzy
from ._strider import Simulation, StriderError
from ._strider import episode_count as _episode_count
from ._strider import merge_json as _merge_json
from ._strider import run as _run

__all__ = ["run", "merge", "episode_count", "Simulation", "StriderError", "fuzzy"]

PathLike = Union[str, "os.PathLike[str]"]


def run(
    map: PathLike,
    *,
    episodes: Optional[int] = None,
    body: str = "animated",
    seed: int = 1,
    rules: Optional[PathLike] = None,
    scen: Optional[PathLike] = None,
    threads: Optional[int] = None,
    shard: Optional[Tuple[int, int]] = None,
) -> dict:
    """Run navigation episodes headless, as ``strider run MAP --format json`` does.

    Args:
        map: a ``.rhai`` map, a plain text world (``.txt``), a MovingAI ``.map``, a BARN
            ``world_N.world``, a folder of worlds, or ``"random:KIND"`` (sparse, semi,
            cluttered, rooms, maze, grid) for seeded random worlds.
        episodes: number of episodes (default: one per task, or 1 for random worlds).
        body: ``"animated"`` (the RL-animated character) or ``"disc"``.
        seed: the run's seed; episode ``i`` depends only on it and ``i``.
        rules: a ``.rhai`` navigation rule script (default: built in).
        scen: a MovingAI scenario file (default: ``MAP.scen`` when it exists).
        threads: worker threads (default: all cores); results do not depend on it.
        shard: ``(I, N)`` runs only episodes ``I, I+N, I+2N, …`` (``--shard I/N``).

    Returns:
        ``{"summary": {...}, "episodes": [{...}, ...]}``, the same object, bit for bit, that
        the command line prints (episodes that miss their goal are data here, not an error).

    Raises:
        StriderError: a missing or malformed file, a bad argument.
    """
    return _run(
        os.fspath(map),
        episodes=episodes,
        body=body,
        seed=seed,
        rules=None if rules is None else os.fspath(rules),
        scen=None if scen is None else os.fspath(scen),
        threads=threads,
        shard=None if shard is None else (int(shard[0]), int(shard[1])),
    )


def merge(outputs: Iterable[Union[dict, str]]) -> dict:
    """Join the outputs of a run's shards (dicts from ``run(..., shard=(I, N))`` for every I, or
    the JSON texts ``strider run --shard I/N`` printed) into what the whole run returns, as
    ``strider merge`` does: each carries its run's identity (``"run"``), and anything but
    exactly one whole run (a shard missing or repeated, shards of another run, a shard cut
    short) raises :class:`StriderError`."""
    texts = [o if isinstance(o, str) else json.dumps(o) for o in outputs]
    return _merge_json(texts)


def episode_count(map: PathLike, *, episodes: Optional[int] = None, scen: Optional[PathLike] = None) -> int:
    """How many episodes a run of ``map`` has: ``episodes``, or one per task (one for random
    worlds)."""
    return _episode_count(os.fspath(map), episodes=episodes, scen=None if scen is None else os.fspath(scen))


