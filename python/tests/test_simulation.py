"""`strider.Simulation` steps exactly the episode `strider.run` runs, and reads as arrays."""

import numpy as np
import pytest

import strider


@pytest.mark.parametrize("map,body,episode", [("random:semi", "disc", 2), ("maps/semi_cluttered.rhai", "animated", 0)])
def test_a_simulation_is_the_runs_episode(repo, monkeypatch, map, body, episode):
    monkeypatch.chdir(repo)
    record = strider.run(map, body=body, seed=4, episodes=episode + 1)["episodes"][episode]
    sim = strider.Simulation(map, body=body, seed=4, episode=episode)
    assert not sim.done and sim.time_s == 0.0
    while not sim.step(50):
        pass
    m = sim.metrics[0]
    for key in ("time_s", "path_length_m", "min_clearance_m", "collisions", "stalls", "steps", "boundary_follows"):
        assert m[key] == record[key], key
    assert sim.outcomes == ["reached" if record["reached"] else "timed_out"]
    assert sim.scenario == record["scenario"]


def test_state_reads_as_arrays():
    sim = strider.Simulation("random:semi", body="disc", seed=1)
    assert sim.scan.shape == (1, 0)
    start = sim.positions.copy()
    sim.step(20)
    assert sim.positions.shape == (1, 2) and sim.positions.dtype == np.float64
    assert sim.headings.shape == (1,) and sim.speeds.shape == (1,)
    assert sim.goals.shape == (1, 2)
    assert np.linalg.norm(sim.positions - start) > 0.1
    assert sim.scan.shape == (1, 72) and np.all(sim.scan >= 0) and np.all(sim.scan <= sim.limits["range_m"])
    scan = sim.range_scan(16)
    assert scan.shape == (16,) and np.all((scan >= 0) & (scan <= sim.limits["range_m"]))
    task = sim.task()
    assert set(task) == {"start", "start_heading", "goal", "goal_radius", "time_limit_s"}


def test_frame_is_an_rgb_picture():
    sim = strider.Simulation("random:semi", body="disc", seed=1)
    sim.step(5)
    frame = sim.frame(160, 120)
    assert frame.shape == (120, 160, 3) and frame.dtype == np.uint8
    # A white background with darker obstacles and agent on it.
    assert (frame == 255).all(axis=2).mean() > 0.3
    assert (frame < 128).any()
    with pytest.raises(strider.StriderError):
        sim.frame(0, 10)


def test_reset_replays_the_same_episode():
    sim = strider.Simulation("random:cluttered", body="disc", seed=7)
    sim.step(100)
    first = sim.positions.copy()
    sim.reset()
    assert sim.time_s == 0.0
    sim.step(100)
    assert np.array_equal(sim.positions, first)
    sim.reset(episode=1)
    assert sim.episode == 1
    sim.step(100)
    assert not np.array_equal(sim.positions, first)


def test_driving_by_hand_follows_the_command():
    sim = strider.Simulation("random:sparse", body="disc", seed=2)
    h0 = sim.headings[0]
    sim.drive(1.0, 0.0)
    sim.step(10)
    assert sim.speeds[0] == 0.0
    assert sim.headings[0] != h0
    sim.release()
    sim.step(10)


def test_no_way_round_is_refused_with_its_reason(tmp_path):
    # A corridor, the only way through a closed room, barred at 1.1 m: too low to duck under,
    # too high to step over.
    walls = [(4.0, 0.6, 6.0, 0.2), (4.0, -0.6, 6.0, 0.2), (2.5, 3.1, 8.2, 0.2), (2.5, -3.1, 8.2, 0.2),
             (-1.6, 0.0, 0.2, 6.4), (6.6, 0.0, 0.2, 6.4), (1.1, 1.8, 0.2, 2.4), (1.1, -1.8, 0.2, 2.4)]
    text = "start -1 0 0\ngoal 6 0\n" + "".join(f"box {x} {y} {w} {h}\n" for x, y, w, h in walls)
    text += "z_extent 1.1 1.2\nbox 4 0 0.1 1.0\n"
    world = tmp_path / "barred.txt"
    world.write_text(text)
    sim = strider.Simulation(str(world), body="animated")
    assert sim.done and sim.outcomes == ["refused"]
    record = strider.run(str(world), body="animated")["episodes"][0]
    assert not record["reached"] and "underside 1.10 m" in record["refusal"]
    # The disc, with no third dimension, walks under the bar.
    assert strider.run(str(world), body="disc")["episodes"][0].get("refusal") is None
