"""navground's side of benches/peers/navground.sh, and the world both programs run.

    python navground_bench.py WORLD.txt [SECONDS] [SEED]

Writes the world to WORLD.txt in strider's plain text format: one agent of radius 0.3 m going
corner to corner of a 16 m square (start (0.5, 0.5), goal (15.5, 15.5), goal radius 0.5 m)
among 30 circles of radius 0.2-0.6 m scattered over it (seeded; none within 0.5 m of the
start or goal disc, none overlapping another). Then builds the same world in navground: the
agent with two-wheel differential-drive kinematics (wheel axis 0.6 m, 1.5 m/s, strider's disc
speed), the HL behaviour with a 5 m horizon fed by a state estimation of 5 m range, a
waypoint task at the goal with the same tolerance, time step 0.05 s. It runs the episode once
step by step to count the steps to the goal, then replays whole episodes in navground's own
loop (World.run, no Python per step) for about SECONDS and prints

    navground steps N reached R
    navground steps/s X
"""

import math
import random
import sys
import time

from navground import core, sim

SIDE = 16.0
START = (0.5, 0.5)
GOAL = (15.5, 15.5)
RADIUS = 0.3
GOAL_RADIUS = 0.5
SPEED = 1.5
RANGE = 5.0
DT = 0.05
MAX_STEPS = 20_000


def circles(seed):
    rng = random.Random(seed)
    out = []
    while len(out) < 30:
        r = rng.uniform(0.2, 0.6)
        x, y = rng.uniform(0.0, SIDE), rng.uniform(0.0, SIDE)
        if any(math.dist((x, y), p) < r + RADIUS + 0.5 for p in (START, GOAL)):
            continue
        if any(math.dist((x, y), (cx, cy)) < r + cr for cx, cy, cr in out):
            continue
        out.append((x, y, r))
    return out


def write_world(path, obstacles):
    with open(path, "w") as f:
        f.write("# navground peer world: 30 circles over a 16 m square, corner to corner\n")
        f.write(f"agent_radius {RADIUS}\n")
        f.write(f"start {START[0]} {START[1]} {math.atan2(GOAL[1] - START[1], GOAL[0] - START[0])!r}\n")
        f.write(f"goal {GOAL[0]} {GOAL[1]} {GOAL_RADIUS}\n")
        f.write(f"time_limit 120\n")
        for x, y, r in obstacles:
            f.write(f"cyl {x!r} {y!r} {r!r}\n")


def world(obstacles):
    w = sim.World()
    for x, y, r in obstacles:
        w.add_obstacle(sim.Obstacle((x, y), r))
    kinematics = core.kinematics.TwoWheelsDifferentialDriveKinematics(max_speed=SPEED, wheel_axis=2 * RADIUS)
    behavior = core.behaviors.HLBehavior(kinematics=kinematics, radius=RADIUS)
    behavior.optimal_speed = SPEED
    behavior.horizon = RANGE
    agent = sim.Agent(
        radius=RADIUS,
        behavior=behavior,
        kinematics=kinematics,
        task=sim.tasks.WaypointsTask(waypoints=[GOAL], loop=False, tolerance=GOAL_RADIUS),
        state_estimations=[sim.state_estimations.BoundedStateEstimation(range=RANGE)],
    )
    agent.pose = core.Pose2(START, math.atan2(GOAL[1] - START[1], GOAL[0] - START[0]))
    w.add_agent(agent)
    return w, agent


def main():
    path = sys.argv[1]
    seconds = float(sys.argv[2]) if len(sys.argv) > 2 else 3.0
    seed = int(sys.argv[3]) if len(sys.argv) > 3 else 27
    obstacles = circles(seed)
    write_world(path, obstacles)
    # The steps one episode takes to the goal.
    w, agent = world(obstacles)
    steps = 0
    while not agent.task.done() and steps < MAX_STEPS:
        w.update(DT)
        steps += 1
    reached = agent.task.done()
    print(f"navground steps {steps} reached {int(reached)}")
    # Whole episodes in navground's own loop; building each world is left out.
    total, spent = 0, 0.0
    while spent < seconds:
        w, agent = world(obstacles)
        t0 = time.perf_counter()
        w.run(steps, DT)
        spent += time.perf_counter() - t0
        total += steps
    print(f"navground steps/s {total / spent:.0f}")


if __name__ == "__main__":
    main()
