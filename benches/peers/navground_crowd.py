"""navground's side of the crowd comparison (benches/peers/navground_crowd.sh): runs a
resolved crowd text world (the output of `strider gen CASE.xml --seed S`) with navground's
behaviours and prints one line of measures per world and behaviour.

    python navground_crowd.py WORLD.txt [WORLD.txt ...] [--behaviors HL,ORCA,HRVO,SocialForce]
        [--dt 0.05] [--cap SECONDS] [--range 5] [--trajectory-out DIR] [--json]

The same agents as strider's: each world's agents with their radii, start poses and initial
speeds, holonomic (omnidirectional kinematics, the fastest of its desired speeds as top speed),
sensing its neighbours and the walls within --range metres. Each agent does its goals in
order, as SteerSuite does: a `seek` (or `seek_region`, walked to its target point) is
achieved when the agent's centre is within its radius of the target (inside the box for a
region), an `idle` stands; a goal ends once achieved or once its duration has passed, and the
goal's desired speed is the behaviour's optimal speed meanwhile. An agent that ended its last
goal is taken out of the world (disabled), unless the world says `crowd stay`.

What navground cannot express here is skipped, and counted: goals that follow or flee
another agent (`seek_agent`, `flee_agent`), flee a point (`flee`) or follow a flow (`flow`,
`flow_dynamic`) have no navground target; such a goal ends at once.

Time step --dt (0.05 s), cap --cap seconds (400 s, 600 s from 1,000 agents). Measures per
world and behaviour:
  agents, reached (agents that achieved their last goal), mean_time_to_goal_s (over those),
  collisions (navground's own colliding pairs, each counted once per contact: agent-agent and
  agent-wall), unsupported_goals, steps, agent_steps_per_s (active agents times steps over the
  seconds spent in navground's update alone, one thread).
With --trajectory-out DIR, DIR/NAME-BEHAVIOR/episode_0.csv has the rows
`time_s,agent,x,y,heading_rad,radius` of every agent in the world at every step (time 0 and
after each step), agents numbered from 0 in file order: what crowd_check.py reads.
"""

import argparse
import json
import math
import os
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import crowd_world  # noqa: E402
from navground import core, sim  # noqa: E402

BEHAVIORS = {
    "HL": core.behaviors.HLBehavior,
    "ORCA": core.behaviors.ORCABehavior,
    "HRVO": core.behaviors.HRVOBehavior,
    "SocialForce": core.behaviors.SocialForceBehavior,
}
SUPPORTED = ("seek", "seek_region", "idle")


def cap_for(n_agents):
    return 600.0 if n_agents >= 1000 else 400.0


def build(world, behavior_name, sensing_range):
    w = sim.World()
    for o in world.obstacles:
        if o.kind == "circle":
            w.add_obstacle(sim.Obstacle(o.points[0], o.radius))
        else:
            pts = o.points
            for a, b in zip(pts, pts[1:] + pts[:1]):
                w.add_wall(sim.Wall(a, b))
    agents = []
    for a in world.agents:
        top = max([g.speed for g in a.goals] + [a.speed, 0.1])
        kinematics = core.kinematics.OmnidirectionalKinematics(max_speed=top, max_angular_speed=10.0)
        behavior = BEHAVIORS[behavior_name](kinematics=kinematics, radius=a.radius)
        behavior.horizon = sensing_range
        agent = sim.Agent(
            radius=a.radius,
            behavior=behavior,
            kinematics=kinematics,
            state_estimations=[sim.state_estimations.BoundedStateEstimation(range=sensing_range)],
        )
        agent.pose = core.Pose2((a.x, a.y), a.yaw)
        if a.speed > 0:
            agent.twist = core.Twist2((a.speed * math.cos(a.yaw), a.speed * math.sin(a.yaw)), 0.0)
        w.add_agent(agent)
        agents.append(agent)
    return w, agents


class Progress:
    """One agent's place in its goal sequence."""

    def __init__(self, spec, agent):
        self.spec, self.agent = spec, agent
        self.goal = -1
        self.started = 0.0
        self.done_at = None
        self.reached = False
        self.unsupported = 0

    def begin_next(self, t):
        """Starts the next supported goal; False when the sequence is over."""
        while True:
            self.goal += 1
            if self.goal >= len(self.spec.goals):
                return False
            g = self.spec.goals[self.goal]
            if g.kind not in SUPPORTED:
                self.unsupported += 1
                continue
            self.started = t
            b = self.agent.behavior
            b.optimal_speed = g.speed
            if g.kind == "idle":
                p = self.agent.position
                b.target = core.Target.Point((float(p[0]), float(p[1])), 0.0)
                b.optimal_speed = 0.0
            else:
                b.target = core.Target.Point(g.args[:2], 0.0)
            return True

    def achieved(self):
        g = self.spec.goals[self.goal]
        p = self.agent.position
        if g.kind == "seek":
            return math.dist((float(p[0]), float(p[1])), g.args[:2]) < self.spec.radius
        if g.kind == "seek_region":
            _, _, x0, y0, x1, y1 = g.args
            return x0 <= p[0] <= x1 and y0 <= p[1] <= y1
        return False

    def update(self, t):
        """After a step at time t: moves on past ended goals; False once the agent is done."""
        while True:
            g = self.spec.goals[self.goal]
            hit = self.achieved()
            if not hit and t - self.started < g.duration:
                return True
            if not self.begin_next(t):
                self.done_at = t
                self.reached = hit or g.kind == "idle"
                return False


def run(world, behavior_name, dt, cap, sensing_range, trajectory_dir=None):
    w, agents = build(world, behavior_name, sensing_range)
    progress = [Progress(spec, agent) for spec, agent in zip(world.agents, agents)]
    active = []
    for i, p in enumerate(progress):
        if p.begin_next(0.0):
            active.append(i)
        else:
            p.done_at, p.reached = 0.0, False
            if not world.stay:
                agents[i].enabled = False
    rows = None
    if trajectory_dir:
        os.makedirs(trajectory_dir, exist_ok=True)
        rows = open(os.path.join(trajectory_dir, "episode_0.csv"), "w")
        rows.write("time_s,agent,x,y,heading_rad,radius\n")

    def write_rows(t, ids):
        if rows is not None:
            for i in ids:
                a = agents[i]
                p = a.position
                rows.write(f"{t!r},{i},{float(p[0])!r},{float(p[1])!r},{float(a.orientation)!r},{world.agents[i].radius!r}\n")

    present = list(range(len(agents))) if world.stay else list(active)
    write_rows(0.0, present)
    steps, agent_steps, spent = 0, 0, 0.0
    contacts, touching = 0, set()
    max_steps = int(math.ceil(cap / dt - 1e-9))
    while active and steps < max_steps:
        t0 = time.perf_counter()
        w.update(dt)
        spent += time.perf_counter() - t0
        agent_steps += len(present)
        steps += 1
        t = steps * dt
        now = set()
        for a, b in w.collisions:
            now.add((min(a._uid, b._uid), max(a._uid, b._uid)))
        contacts += len(now - touching)
        touching = now
        write_rows(t, present)
        still = []
        for i in active:
            if progress[i].update(t):
                still.append(i)
            elif not world.stay:
                agents[i].enabled = False
        active = still
        if not world.stay:
            present = active
    if rows is not None:
        rows.close()
    reached = [p for p in progress if p.reached]
    mean_time = sum(p.done_at for p in reached) / len(reached) if reached else None
    return {
        "agents": len(agents),
        "reached": len(reached),
        "mean_time_to_goal_s": mean_time,
        "collisions": contacts,
        "unsupported_goals": sum(p.unsupported for p in progress),
        "steps": steps,
        "agent_steps_per_s": agent_steps / spent if spent > 0 else None,
    }


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("worlds", nargs="+")
    ap.add_argument("--behaviors", default="HL,ORCA,HRVO,SocialForce")
    ap.add_argument("--dt", type=float, default=0.05)
    ap.add_argument("--cap", type=float, default=None, help="seconds (default 400, 600 from 1,000 agents)")
    ap.add_argument("--range", type=float, default=5.0, dest="sensing_range")
    ap.add_argument("--trajectory-out", default=None)
    ap.add_argument("--json", action="store_true", help="one JSON object per line instead of a table")
    args = ap.parse_args()
    names = [b.strip() for b in args.behaviors.split(",") if b.strip()]
    for b in names:
        if b not in BEHAVIORS:
            sys.exit(f"unknown behavior {b}: expected one of {', '.join(BEHAVIORS)}")
    if not args.json:
        print(f"{'world':36} {'behavior':11} {'agents':>6} {'reached':>7} {'mean_t_s':>9} {'collis':>7} {'unsup':>5} {'steps':>6} {'agent-steps/s':>13}")
    for path in args.worlds:
        world = crowd_world.read(path)
        name = os.path.splitext(os.path.basename(path))[0]
        cap = args.cap if args.cap is not None else cap_for(len(world.agents))
        for b in names:
            tdir = os.path.join(args.trajectory_out, f"{name}-{b}") if args.trajectory_out else None
            r = run(world, b, args.dt, cap, args.sensing_range, tdir)
            r.update({"world": name, "behavior": b, "cap_s": cap, "dt_s": args.dt})
            if args.json:
                print(json.dumps(r), flush=True)
            else:
                mt = "-" if r["mean_time_to_goal_s"] is None else f"{r['mean_time_to_goal_s']:.2f}"
                rate = "-" if r["agent_steps_per_s"] is None else f"{r['agent_steps_per_s']:.0f}"
                print(
                    f"{name:36} {b:11} {r['agents']:6d} {r['reached']:7d} {mt:>9} {r['collisions']:7d} "
                    f"{r['unsupported_goals']:5d} {r['steps']:6d} {rate:>13}",
                    flush=True,
                )


if __name__ == "__main__":
    main()
