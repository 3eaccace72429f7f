"""benches/peers/crowd_check.py, the independent overlap check of crowd trajectories, on
worlds and trajectories written here: exact distances, contacts counted once per contact."""

import os
import sys

import pytest

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "..", "benches", "peers"))

import crowd_check  # noqa: E402
import crowd_world  # noqa: E402

WORLD = """\
crowd
agent 0 0 0 0.5 0
seek 9 0 1.3 10
agent 5 5 0 0.5 0
idle 0 10
z_extent 0 1
# a box turned 45 degrees about (10, 0): its corner nearest the origin is at (10 - sqrt(2), 0)
box 10 0 2 2 0.7853981633974483
# an L whose notch holds (21, 1) clear of it, though its hull would not
poly 20 0 24 0 24 4 22 4 22 2 20 2
cyl 30 0 1
z_extent 0 0.3
box 40 0 2 2
"""


def rows(steps):
    """CSV text of `steps`: lists of (agent, x, y, radius) per step, 0.05 s apart."""
    out = ["time_s,agent,x,y,heading_rad,radius"]
    for k, step in enumerate(steps):
        for a, x, y, r in step:
            out.append(f"{k * 0.05!r},{a},{x!r},{y!r},0.0,{r!r}")
    return "\n".join(out) + "\n"


@pytest.fixture
def world(tmp_path):
    path = tmp_path / "w.txt"
    path.write_text(WORLD)
    return crowd_world.read(str(path))


def test_the_world_keeps_its_walls_and_agents(world):
    assert [a.radius for a in world.agents] == [0.5, 0.5]
    assert world.agents[0].goals[0].kind == "seek"
    # The low box is ground to step over, not a wall.
    assert [o.kind for o in world.obstacles] == ["polygon", "polygon", "circle"]


def test_agent_contacts_are_counted_once_each(world, tmp_path):
    apart, touching = 1.2, 0.9
    steps = [
        [(0, 0.0, 0.0, 0.5), (1, apart, 0.0, 0.5)],
        [(0, 0.0, 0.0, 0.5), (1, touching, 0.0, 0.5)],
        [(0, 0.0, 0.0, 0.5), (1, touching, 0.0, 0.5)],
        [(0, 0.0, 0.0, 0.5), (1, apart, 0.0, 0.5)],
        [(0, 0.0, 0.0, 0.5), (1, 0.0, 0.95, 0.5)],
        # Agent 1 has left the world; agent 0 alone.
        [(0, 0.0, 0.0, 0.5)],
    ]
    path = tmp_path / "episode_0.csv"
    path.write_text(rows(steps))
    r = crowd_check.check(world, str(path), 1e-6)
    assert r["steps"] == 6 and r["agents_seen"] == 2
    assert r["agent_agent_overlaps"] == 2
    first, second = r["agent_agent"]
    assert first["agents"] == [0, 1] and (first["from_s"], first["to_s"]) == (0.05, 0.1)
    assert first["deepest_m"] == pytest.approx(0.1)
    assert second["from_s"] == pytest.approx(0.2) and second["deepest_m"] == pytest.approx(0.05)
    assert r["agent_obstacle_overlaps"] == 0


def test_obstacle_distances_are_exact(world, tmp_path):
    corner = 10.0 - 2.0**0.5
    steps = [
        [
            # Just clear of the turned box's corner, then just into it.
            (0, corner - 0.5 - 1e-3, 0.0, 0.5),
            # In the L's notch: clear, though inside its hull.
            (1, 21.0, 3.0, 0.5),
            # Beside the cylinder, clear.
            (2, 31.6, 0.0, 0.5),
            # On the low box: ground, not a wall.
            (3, 40.0, 0.0, 0.5),
        ],
        [
            (0, corner - 0.5 + 1e-3, 0.0, 0.5),
            (1, 21.0, 2.4, 0.5),
            (2, 31.4, 0.0, 0.5),
            (3, 40.0, 0.0, 0.5),
        ],
    ]
    path = tmp_path / "episode_3.csv"
    path.write_text(rows(steps))
    r = crowd_check.check(world, str(path), 1e-6)
    hits = {(c["agent"], c["obstacle"]): c for c in r["agent_obstacle"]}
    assert set(hits) == {(0, 1), (1, 2), (2, 3)}
    assert all(c["from_s"] == 0.05 for c in hits.values())
    assert hits[(0, 1)]["deepest_m"] == pytest.approx(1e-3, abs=1e-9)
    assert hits[(1, 2)]["deepest_m"] == pytest.approx(0.1)
    assert hits[(2, 3)]["deepest_m"] == pytest.approx(0.1)


def test_the_command_line_exits_1_on_overlaps_and_2_on_bad_input(tmp_path, monkeypatch, capsys):
    (tmp_path / "w.txt").write_text(WORLD)
    out = tmp_path / "run"
    out.mkdir()
    (out / "episode_0.csv").write_text(rows([[(0, 0.0, 0.0, 0.5), (1, 3.0, 0.0, 0.5)]]))
    monkeypatch.setattr(sys, "argv", ["crowd_check.py", str(tmp_path / "w.txt"), str(out)])
    assert crowd_check.main() == 0
    (out / "episode_1.csv").write_text(rows([[(0, 0.0, 0.0, 0.5), (1, 0.5, 0.0, 0.5)]]))
    assert crowd_check.main() == 1
    assert "agent-agent overlaps 1" in capsys.readouterr().out
    (out / "episode_2.csv").write_text("t,a\n")
    assert crowd_check.main() == 2
