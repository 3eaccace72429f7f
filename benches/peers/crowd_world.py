"""strider's plain text worlds with a crowd, read in Python for the crowd peers and checks
(navground_crowd.py, crowd_check.py). No dependency beyond the standard library.

    world = read("case.txt")
    world.agents     # Agent(name, x, y, yaw, radius, speed, goals), in file order
    world.obstacles  # Obstacle(kind, outline or centre and radius, z_min, z_max), walls only
    world.stay       # whether arrived agents stay

Reads what the format says (src/maps/text.rs, src/maps/text/crowd.rs): `agent_radius`,
`z_extent`, `cyl`, `box`, `convex`, `poly`, `start`/`goal`/`time_limit` pairs (agents of the
crowd: the world's radius, speed 0, one seek of the goal at 1.3 m/s for the time limit), and
the crowd lines `crowd [stay]`, `agent`, `seek`, `flee`, `seek_agent`, `flee_agent`,
`seek_region`, `flow`, `flow_dynamic`, `idle`. Terrain and benchmark lines are skipped.
Obstacles are kept as outlines (boxes turned to their four corners, convex point sets to
their hull) or circles; the ones a walker steps over (bottom on the ground, top at most
0.45 m) or passes under (bottom at 1 m or above) are not walls and are dropped unless
`all_obstacles` is asked.
"""

import math
from dataclasses import dataclass, field

DEFAULT_AGENT_RADIUS = 0.3
DEFAULT_Z = (0.0, 2.0)
DEFAULT_DESIRED_SPEED = 1.3
STEP_ONTO_MAX_Z = 0.45
UPPER_BAND_MIN_Z = 1.0
GOAL_KEYWORDS = ("seek", "flee", "seek_agent", "flee_agent", "seek_region", "flow", "flow_dynamic", "idle")


@dataclass
class Goal:
    kind: str  # one of GOAL_KEYWORDS
    args: tuple  # (x, y) | (agent index from 0,) | (x, y, xmin, ymin, xmax, ymax) | (dx, dy) | (kind,) | ()
    speed: float
    duration: float

    def static_target(self):
        if self.kind in ("seek", "seek_region"):
            return self.args[0], self.args[1]
        return None


@dataclass
class Agent:
    name: str
    x: float
    y: float
    yaw: float
    radius: float
    speed: float
    goals: list = field(default_factory=list)


@dataclass
class Obstacle:
    kind: str  # "circle" or "polygon"
    points: list  # polygon outline [(x, y), ...] (either orientation), or [(cx, cy)] for a circle
    radius: float  # circle radius (0 for polygons)
    z_min: float
    z_max: float

    def is_wall(self):
        low = self.z_min <= 0.0 and self.z_max <= STEP_ONTO_MAX_Z
        return not low and self.z_min < UPPER_BAND_MIN_Z


@dataclass
class World:
    agents: list
    obstacles: list
    stay: bool


def hull(points):
    pts = sorted(set(points))
    if len(pts) < 3:
        return pts

    def cross(o, a, b):
        return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])

    lower, upper = [], []
    for p in pts:
        while len(lower) >= 2 and cross(lower[-2], lower[-1], p) <= 0:
            lower.pop()
        lower.append(p)
    for p in reversed(pts):
        while len(upper) >= 2 and cross(upper[-2], upper[-1], p) <= 0:
            upper.pop()
        upper.append(p)
    return lower[:-1] + upper[:-1]


def box_corners(cx, cy, w, h, yaw):
    c, s = math.cos(yaw), math.sin(yaw)
    out = []
    for dx, dy in ((-w / 2, -h / 2), (w / 2, -h / 2), (w / 2, h / 2), (-w / 2, h / 2)):
        out.append((cx + c * dx - s * dy, cy + s * dx + c * dy))
    return out


def read(path, all_obstacles=False):
    radius = DEFAULT_AGENT_RADIUS
    z = DEFAULT_Z
    obstacles = []
    entries = []  # ("agent", Agent) or ("task", [start, goal, time_limit])
    pending = []
    last_task = None
    crowd = False
    stay = False
    with open(path) as f:
        for number, line in enumerate(f, 1):
            words = line.split("#", 1)[0].split()
            if not words:
                continue
            kw, args = words[0], words[1:]

            def nums(a=args):
                return [float(v) for v in a]

            try:
                if kw == "agent_radius":
                    radius = float(args[0])
                elif kw == "z_extent":
                    z = (float(args[0]), float(args[1]))
                elif kw == "cyl":
                    x, y, r = nums()
                    obstacles.append(Obstacle("circle", [(x, y)], r, *z))
                elif kw == "box":
                    v = nums()
                    obstacles.append(Obstacle("polygon", box_corners(*v[:4], v[4] if len(v) > 4 else 0.0), 0.0, *z))
                elif kw in ("convex", "poly"):
                    v = nums()
                    pts = list(zip(v[0::2], v[1::2]))
                    obstacles.append(Obstacle("polygon", hull(pts) if kw == "convex" else pts, 0.0, *z))
                elif kw == "start":
                    v = nums()
                    pending.append((v[0], v[1], v[2] if len(v) > 2 else 0.0))
                elif kw == "goal":
                    v = nums()
                    start = pending.pop(0)
                    d = math.dist(start[:2], v[:2])
                    last_task = [start, (v[0], v[1]), min(max(10.0 * d, 60.0), 86400.0)]
                    entries.append(("task", last_task))
                elif kw == "time_limit":
                    last_task[2] = float(args[0])
                elif kw == "crowd":
                    crowd = True
                    stay = args[:1] == ["stay"]
                elif kw == "agent":
                    v = nums(args[:5])
                    entries.append(("agent", Agent(args[5] if len(args) > 5 else "", *v)))
                    crowd = True
                elif kw in GOAL_KEYWORDS:
                    agent = next(a for k, a in reversed(entries) if k == "agent")
                    speed, duration = float(args[-2]), float(args[-1])
                    lead = args[:-2]
                    if kw in ("seek_agent", "flee_agent"):
                        goal_args = (int(lead[0]) - 1,)
                    elif kw == "flow_dynamic":
                        goal_args = (lead[0],)
                    else:
                        goal_args = tuple(nums(lead))
                    agent.goals.append(Goal(kw, goal_args, speed, duration))
            except (ValueError, IndexError, StopIteration) as e:
                raise ValueError(f"{path}:{number}: cannot read `{line.strip()}`: {e}") from e
    if not crowd:
        raise ValueError(f"{path}: not a crowd world (no `crowd` or `agent` line)")
    agents = []
    for kind, e in entries:
        if kind == "agent":
            agents.append(e)
        else:
            (sx, sy, yaw), (gx, gy), limit = e
            agents.append(Agent("", sx, sy, yaw, radius, 0.0, [Goal("seek", (gx, gy), DEFAULT_DESIRED_SPEED, limit)]))
    if not all_obstacles:
        obstacles = [o for o in obstacles if o.is_wall()]
    return World(agents, obstacles, stay)
