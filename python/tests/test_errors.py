"""Bad input from Python raises a clear exception carrying strider's located message."""

import numpy as np
import pytest

import strider
from strider.fuzzy import Engine


def test_a_missing_map_names_the_file(tmp_path):
    missing = tmp_path / "nowhere.rhai"
    with pytest.raises(strider.StriderError, match="nowhere.rhai") as e:
        strider.run(missing)
    assert isinstance(e.value, ValueError)
    assert e.value.file == str(missing)


def test_bad_map_text_gives_file_line_and_column(tmp_path):
    world = tmp_path / "bad.txt"
    world.write_text("box 0 0 1 1\nstart 1 1 0\ngoal 5 5\nwobble 3\n")
    with pytest.raises(strider.StriderError) as e:
        strider.run(world, body="disc")
    assert str(e.value).startswith(f"{world}:"), str(e.value)
    assert e.value.line >= 1


def test_a_bad_rule_script_is_located(tmp_path):
    rules = tmp_path / "rules.rhai"
    rules.write_text("let x = ;\n")
    with pytest.raises(strider.StriderError, match=r"rules\.rhai:1:\d+"):
        strider.run("random:semi", body="disc", rules=rules)


def test_bad_fll_is_located(repo):
    text = (repo / "tests/fixtures/fuzzy/bad_rule.fll").read_text()
    with pytest.raises(strider.StriderError, match=r"bad_rule\.fll:\d+:\d+"):
        Engine.from_fll(text, file="bad_rule.fll")


@pytest.mark.parametrize(
    "call",
    [
        lambda: strider.run(42),
        lambda: strider.run("random:semi", episodes="three"),
        lambda: strider.run("random:semi", seed=1.5),
        lambda: strider.Simulation("random:semi", body="disc").step("x"),
        lambda: Engine.from_fll(b"Engine: e"),
        lambda: Engine.from_fll("Engine: e").process([1, 2]),
    ],
)
def test_wrong_types_raise_type_errors(call):
    with pytest.raises(TypeError):
        call()


@pytest.mark.parametrize(
    "kw,match",
    [
        (dict(body="robot"), "body must be"),
        (dict(episodes=0), "--episodes"),
        (dict(threads=0), "--threads"),
        (dict(shard=(3, 2)), "shard"),
    ],
)
def test_bad_arguments_raise(kw, match):
    with pytest.raises(strider.StriderError, match=match):
        strider.run("random:semi", **{"body": "disc", **kw})


def test_negative_seed_overflows():
    with pytest.raises(OverflowError):
        strider.run("random:semi", seed=-1)


def test_nan_commands_are_refused():
    sim = strider.Simulation("random:semi", body="disc")
    with pytest.raises(strider.StriderError, match="finite"):
        sim.drive(float("nan"), 1.0)
    with pytest.raises(strider.StriderError, match="agent 3"):
        sim.drive(0.0, 1.0, agent=3)


def test_fuzzy_inputs_are_checked(repo):
    engine = Engine.from_fll((repo / "tests/fixtures/fuzzy/tipper.fll").read_text())
    good = {name: 1.0 for name in engine.inputs}
    with pytest.raises(strider.StriderError, match="missing"):
        engine.process({})
    with pytest.raises(strider.StriderError, match="not an input"):
        engine.process({**good, "nope": 1.0})
    with pytest.raises(strider.StriderError, match="broadcast"):
        engine.process({"service": np.zeros(2), "food": np.zeros(3)})
    with pytest.raises(TypeError):
        engine.process({n: "high" for n in engine.inputs})


@pytest.mark.parametrize("value", [None, "1.5", [1.0, None], np.array(["1"]), 1j, [1.0, [2.0, 3.0]]])
def test_fuzzy_inputs_that_are_not_numbers_raise_type_errors(repo, value):
    engine = Engine.from_fll((repo / "tests/fixtures/fuzzy/tipper.fll").read_text())
    inputs = {name: 1.0 for name in engine.inputs}
    inputs[engine.inputs[0]] = value
    with pytest.raises(TypeError, match=repr(engine.inputs[0])):
        engine.process(inputs)
    # Numbers of every kind still go in.
    inputs[engine.inputs[0]] = [True, 2, 3.5, np.float32(1.0)]
    assert engine.process(inputs)[engine.outputs[0]].shape == (4,)
