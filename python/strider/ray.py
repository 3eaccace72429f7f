"""strider batches spread over a Ray cluster.

``strider.ray.run`` splits a run's episodes into interleaved shards (episode ``i`` goes to
shard ``i mod N``), runs each shard as a Ray task with ``strider.run(..., shard=(I, N))`` and
joins them as ``strider merge`` does. Every episode depends only on the run's seed and its own
number, so the result is exactly what ``strider.run`` returns on one machine.

Locally ``ray.init()`` is enough (it is called for you when Ray is not running). On a cluster,
start the head with ``ray start --head``, each worker with ``ray start --address=HEAD:6379``,
and call ``ray.init(address="auto")`` before ``strider.ray.run``; maps, rules and scenario
files must be at the same path on every node (``random:KIND`` maps need no files).
"""

from __future__ import annotations

import os
from typing import Optional, Union

from . import episode_count, merge
from . import run as _local_run

__all__ = ["run"]

PathLike = Union[str, "os.PathLike[str]"]


def _shard(map, episodes, body, seed, rules, scen, threads, index, count):
    return _local_run(
        map, episodes=episodes, body=body, seed=seed, rules=rules, scen=scen, threads=threads, shard=(index, count)
    )


def run(
    map: PathLike,
    *,
    episodes: Optional[int] = None,
    body: str = "animated",
    seed: int = 1,
    rules: Optional[PathLike] = None,
    scen: Optional[PathLike] = None,
    shards: Optional[int] = None,
    threads_per_shard: int = 1,
) -> dict:
    """Run episodes as Ray tasks; returns exactly what :func:`strider.run` returns.

    Args:
        map, episodes, body, seed, rules, scen: as for :func:`strider.run`.
        shards: how many Ray tasks (default: the cluster's CPUs divided by
            ``threads_per_shard``, at most one per episode).
        threads_per_shard: CPUs each task asks Ray for and runs its episodes on.
    """
    import ray

    if threads_per_shard < 1:
        raise ValueError(f"threads_per_shard must be at least 1, found {threads_per_shard}")
    total = episode_count(map, episodes=episodes, scen=scen)
    if not ray.is_initialized():
        ray.init()
    if shards is None:
        cpus = int(ray.cluster_resources().get("CPU", 1))
        shards = max(1, cpus // threads_per_shard)
    if shards < 1:
        raise ValueError(f"shards must be at least 1, found {shards}")
    shards = min(shards, total)
    fspath = lambda p: None if p is None else os.fspath(p)  # noqa: E731
    task = ray.remote(num_cpus=threads_per_shard)(_shard)
    refs = [
        task.remote(fspath(map), episodes, body, seed, fspath(rules), fspath(scen), threads_per_shard, i, shards)
        for i in range(shards)
    ]
    return merge(ray.get(refs))
