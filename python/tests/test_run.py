"""`strider.run` returns what `strider run --format json` prints, and merges shards exactly."""

import json
import math
import struct

import pytest

import strider
from conftest import cli_json, without_timing


def bits(doc):
    """Every number of `doc` as its exact bits (so 0.1 + 0.2 never passes for 0.3)."""
    if isinstance(doc, dict):
        return {k: bits(v) for k, v in doc.items()}
    if isinstance(doc, list):
        return [bits(v) for v in doc]
    if isinstance(doc, float):
        return ("f64", struct.pack("<d", doc).hex())
    return doc


CASES = [
    ("random:semi", dict(episodes=6, body="disc", seed=3)),
    ("random:rooms", dict(episodes=3, body="disc", seed=11)),
    ("random:grid", dict(episodes=3, body="animated", seed=2)),
    ("maps/semi_cluttered.rhai", dict()),
    ("maps/u_trap.rhai", dict(body="disc", rules="scripts/nav.rhai")),
    ("tests/fixtures/maps/tiny.map", dict(body="disc")),
    ("maps/terrain_stairs.rhai", dict()),
]


def cli_args(map, kw):
    args = [map]
    for k, v in kw.items():
        args += [f"--{k}", str(v)]
    return args


@pytest.mark.parametrize("map,kw", CASES, ids=[c[0] for c in CASES])
def test_run_equals_the_command_line(cli, repo, monkeypatch, map, kw):
    monkeypatch.chdir(repo)
    expected = cli_json(cli, *cli_args(map, kw))
    got = strider.run(map, **kw)
    assert list(got) == list(expected)
    assert bits(without_timing(got)) == bits(without_timing(expected))
    # Timing figures are present in both or neither.
    assert json.dumps(got, sort_keys=True).count("_ms_") == json.dumps(expected, sort_keys=True).count("_ms_")


def test_results_do_not_depend_on_threads():
    one = strider.run("random:cluttered", episodes=4, body="disc", seed=5, threads=1)
    two = strider.run("random:cluttered", episodes=4, body="disc", seed=5, threads=2)
    assert bits(one) == bits(two)


def test_shards_merge_into_the_whole_run():
    whole = strider.run("random:semi", episodes=7, body="disc", seed=9)
    parts = [strider.run("random:semi", episodes=7, body="disc", seed=9, shard=(i, 3)) for i in range(3)]
    assert [e["episode"] for e in parts[1]["episodes"]] == [1, 4]
    assert bits(strider.merge(reversed(parts))) == bits(whole)


def test_merge_refuses_a_missing_shard():
    parts = [strider.run("random:semi", episodes=4, body="disc", seed=9, shard=(i, 2)) for i in range(2)]
    with pytest.raises(strider.StriderError, match="missing"):
        strider.merge(parts[:1])
    with pytest.raises(strider.StriderError, match="also in"):
        strider.merge([parts[0], parts[0], parts[1]])


def test_merge_refuses_shards_of_another_run_and_seeds_are_strings():
    parts = [strider.run("random:semi", episodes=4, body="disc", seed=9, shard=(i, 2)) for i in range(2)]
    other = strider.run("random:semi", episodes=4, body="disc", seed=8, shard=(1, 2))
    assert parts[0]["run"]["shard"] == "0/2" and parts[0]["run"]["seed"] == "9"
    with pytest.raises(strider.StriderError, match="another seed"):
        strider.merge([parts[0], other])
    with pytest.raises(strider.StriderError, match="no run identity"):
        strider.merge([strider.run("random:semi", episodes=4, body="disc", seed=9)])
    seed = parts[0]["episodes"][0]["seed"]
    assert isinstance(seed, str) and int(seed) > 2**53


def test_a_run_that_misses_its_goal_is_data(repo, monkeypatch):
    monkeypatch.chdir(repo)
    doc = strider.run("random:maze", episodes=1, body="disc", seed=1)
    assert doc["summary"]["episodes"] == 1
    assert math.isfinite(doc["episodes"][0]["time_s"])
