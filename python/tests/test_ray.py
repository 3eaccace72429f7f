"""`strider.ray.run` on a local 2-CPU Ray cluster returns exactly what `strider.run` returns."""

import pytest

import ray

import strider
import strider.ray
from test_run import bits


@pytest.fixture(scope="module")
def cluster():
    ray.init(num_cpus=2, include_dashboard=False, log_to_driver=False, configure_logging=False)
    yield
    ray.shutdown()


@pytest.mark.parametrize(
    "map,kw,shards",
    [
        ("random:semi", dict(episodes=9, body="disc", seed=4), None),
        ("random:rooms", dict(episodes=5, body="animated", seed=2), 3),
        ("maps/semi_cluttered.rhai", dict(episodes=4), 4),
    ],
)
def test_ray_run_equals_run(cluster, repo, monkeypatch, map, kw, shards):
    monkeypatch.chdir(repo)
    local = strider.run(map, **kw)
    spread = strider.ray.run(str(repo / map) if not map.startswith("random:") else map, shards=shards, **kw)
    assert bits(spread) == bits(local)


def test_more_shards_than_episodes(cluster):
    assert bits(strider.ray.run("random:sparse", episodes=2, body="disc", shards=5)) == bits(
        strider.run("random:sparse", episodes=2, body="disc")
    )
