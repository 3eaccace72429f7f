"""An independent check of a crowd run's trajectories: every overlap between two agents and
between an agent and an obstacle, computed from the rows alone.

    python crowd_check.py WORLD.txt TRAJECTORIES... [--tolerance 1e-6] [--all-obstacles]
        [--json] [--max-lines 20]

WORLD.txt is the resolved crowd text world the run played (`strider gen CASE.xml --seed S`,
read by crowd_world.py: its walls, boxes, convex and non-convex polygons and cylinders);
TRAJECTORIES are `--trajectory-out` folders (every `episode_N.csv` in them) or CSV files with
the header `time_s,agent,x,y,heading_rad,radius` and a row per agent in the world per step
(strider's, and navground_crowd.py's). Distances are exact: circle to circle, and circle to
polygon (the distance to the nearest edge, the point inside when the even-odd rule says so).
Two discs overlap when their centres are nearer than the sum of their radii less
--tolerance metres; a disc and an obstacle when its centre is inside the obstacle or nearer
to it than its radius less the tolerance. Obstacles a walker steps over or passes under are
not walls (as strider reads them) unless --all-obstacles.

An overlap is counted once per contact: from the step it begins to the last step it lasts
(a new contact after a separation counts again). Per episode it prints the counts, the
deepest overlap, and the first --max-lines contacts (every contact with --json, one JSON
object per episode). Exits 1 when any overlap is found, 0 when none, 2 on bad input.
Needs numpy.
"""

import argparse
import glob
import json
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import crowd_world  # noqa: E402

COLUMNS = ["time_s", "agent", "x", "y", "heading_rad", "radius"]


def load(path):
    with open(path) as f:
        header = f.readline().strip()
        if header.split(",") != COLUMNS:
            raise ValueError(f"{path}: expected the header {','.join(COLUMNS)}, found `{header}`")
        data = np.loadtxt(f, delimiter=",", ndmin=2, dtype=np.float64)
    if data.size == 0:
        data = np.zeros((0, 6))
    order = np.argsort(data[:, 0], kind="stable")
    data = data[order]
    _, step = np.unique(data[:, 0], return_inverse=True)
    return data, step


def contacts(keys, steps, depth):
    """Groups overlapping rows into contacts: runs of consecutive steps of one key. Returns
    (key, first step, last step, deepest) sorted by first step."""
    if len(keys) == 0:
        return []
    order = np.lexsort((steps, keys))
    k, s, d = keys[order], steps[order], depth[order]
    new = np.ones(len(k), dtype=bool)
    new[1:] = (k[1:] != k[:-1]) | (s[1:] != s[:-1] + 1)
    starts = np.flatnonzero(new)
    ends = np.append(starts[1:], len(k)) - 1
    deepest = np.maximum.reduceat(d, starts)
    out = [(int(k[a]), int(s[a]), int(s[b]), float(m)) for a, b, m in zip(starts, ends, deepest)]
    out.sort(key=lambda c: (c[1], c[0]))
    return out


def agent_pairs(data, step, tolerance):
    """Every overlapping pair of agents in every step: (pair keys, steps, depths)."""
    if len(data) == 0:
        return np.zeros(0, np.int64), np.zeros(0, np.int64), np.zeros(0)
    x, y, r = data[:, 2], data[:, 3], data[:, 5]
    ids = data[:, 1].astype(np.int64)
    n_ids = int(ids.max()) + 1
    cell = max(2.0 * float(r.max()), 1e-3)
    cx = np.floor(x / cell).astype(np.int64)
    cy = np.floor(y / cell).astype(np.int64)
    span = np.int64(1 << 20)
    key = (step.astype(np.int64) * span + (cx - cx.min() + 1)) * span + (cy - cy.min() + 1)
    order = np.argsort(key, kind="stable")
    sk = key[order]
    out_k, out_s, out_d = [], [], []
    for dx, dy in ((0, 0), (1, -1), (1, 0), (1, 1), (0, 1)):
        target = sk + dx * span + dy
        lo = np.searchsorted(sk, target, "left")
        hi = np.searchsorted(sk, target, "right")
        counts = hi - lo
        total = int(counts.sum())
        if total == 0:
            continue
        a = np.repeat(np.arange(len(sk)), counts)
        offsets = np.arange(total) - np.repeat(np.cumsum(counts) - counts, counts)
        b = np.repeat(lo, counts) + offsets
        if dx == 0 and dy == 0:
            keep = a < b
            a, b = a[keep], b[keep]
        i, j = order[a], order[b]
        gap = np.hypot(x[i] - x[j], y[i] - y[j])
        depth = r[i] + r[j] - gap
        hit = depth > tolerance
        i, j, depth = i[hit], j[hit], depth[hit]
        lo_id, hi_id = np.minimum(ids[i], ids[j]), np.maximum(ids[i], ids[j])
        out_k.append(lo_id * n_ids + hi_id)
        out_s.append(step[i])
        out_d.append(depth)
    if not out_k:
        return np.zeros(0, np.int64), np.zeros(0, np.int64), np.zeros(0)
    return np.concatenate(out_k), np.concatenate(out_s).astype(np.int64), np.concatenate(out_d)


def polygon_signed_distance(points, outline):
    """Distance from each point to the polygon's boundary, negative inside (even-odd rule)."""
    a = np.array(outline, dtype=np.float64)
    b = np.roll(a, -1, axis=0)
    px, py = points[:, 0:1], points[:, 1:2]
    ex, ey = (b - a)[:, 0], (b - a)[:, 1]
    length2 = np.maximum(ex * ex + ey * ey, 1e-300)
    t = np.clip(((px - a[:, 0]) * ex + (py - a[:, 1]) * ey) / length2, 0.0, 1.0)
    dist = np.hypot(px - (a[:, 0] + t * ex), py - (a[:, 1] + t * ey)).min(axis=1)
    crosses = ((a[:, 1] > py) != (b[:, 1] > py)) & (
        px < (b[:, 0] - a[:, 0]) * (py - a[:, 1]) / np.where(b[:, 1] == a[:, 1], 1e-300, b[:, 1] - a[:, 1]) + a[:, 0]
    )
    inside = (crosses.sum(axis=1) % 2) == 1
    return np.where(inside, -dist, dist)


def obstacle_hits(data, step, obstacles, tolerance):
    """Every overlap of an agent with an obstacle: (agent * n_obstacles + obstacle, steps, depths)."""
    empty = (np.zeros(0, np.int64), np.zeros(0, np.int64), np.zeros(0))
    if len(data) == 0 or not obstacles:
        return empty
    order = np.argsort(data[:, 2], kind="stable")
    xs = data[order, 2]
    rmax = float(data[:, 5].max())
    out_k, out_s, out_d = [], [], []
    for k, o in enumerate(obstacles):
        pts = np.array(o.points, dtype=np.float64)
        reach = o.radius + rmax
        lo = np.searchsorted(xs, pts[:, 0].min() - reach, "left")
        hi = np.searchsorted(xs, pts[:, 0].max() + reach, "right")
        rows = order[lo:hi]
        y = data[rows, 3]
        rows = rows[(y >= pts[:, 1].min() - reach) & (y <= pts[:, 1].max() + reach)]
        if len(rows) == 0:
            continue
        p = data[rows][:, 2:4]
        if o.kind == "circle":
            signed = np.hypot(p[:, 0] - pts[0, 0], p[:, 1] - pts[0, 1]) - o.radius
        else:
            signed = polygon_signed_distance(p, o.points)
        depth = data[rows, 5] - signed
        hit = depth > tolerance
        rows = rows[hit]
        out_k.append(data[rows, 1].astype(np.int64) * len(obstacles) + k)
        out_s.append(step[rows].astype(np.int64))
        out_d.append(depth[hit])
    if not out_k:
        return empty
    return np.concatenate(out_k), np.concatenate(out_s), np.concatenate(out_d)


def check(world, path, tolerance):
    data, step = load(path)
    times = np.unique(data[:, 0])
    n_ids = int(data[:, 1].max()) + 1 if len(data) else 0
    pair = contacts(*agent_pairs(data, step, tolerance))
    hits = contacts(*obstacle_hits(data, step, world.obstacles, tolerance))
    n_obst = max(len(world.obstacles), 1)
    return {
        "episode": path,
        "steps": int(len(times)),
        "agents_seen": int(len(np.unique(data[:, 1]))) if len(data) else 0,
        "agent_agent_overlaps": len(pair),
        "agent_obstacle_overlaps": len(hits),
        "deepest_agent_agent_m": max((c[3] for c in pair), default=0.0),
        "deepest_agent_obstacle_m": max((c[3] for c in hits), default=0.0),
        "agent_agent": [
            {"agents": [k // n_ids, k % n_ids], "from_s": float(times[a]), "to_s": float(times[b]), "deepest_m": d}
            for k, a, b, d in pair
        ],
        "agent_obstacle": [
            {"agent": k // n_obst, "obstacle": k % n_obst + 1, "from_s": float(times[a]), "to_s": float(times[b]), "deepest_m": d}
            for k, a, b, d in hits
        ],
    }


def episodes(paths):
    out = []
    for p in paths:
        if os.path.isdir(p):
            found = glob.glob(os.path.join(p, "episode_*.csv"))
            out += sorted(found, key=lambda f: int(os.path.basename(f)[8:-4]) if os.path.basename(f)[8:-4].isdigit() else 0)
        else:
            out.append(p)
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("world")
    ap.add_argument("trajectories", nargs="+")
    ap.add_argument("--tolerance", type=float, default=1e-6, help="metres (default 1e-6)")
    ap.add_argument("--all-obstacles", action="store_true")
    ap.add_argument("--json", action="store_true")
    ap.add_argument("--max-lines", type=int, default=20)
    args = ap.parse_args()
    try:
        world = crowd_world.read(args.world, all_obstacles=args.all_obstacles)
        files = episodes(args.trajectories)
        if not files:
            raise ValueError("no episode_N.csv found")
        results = [check(world, f, args.tolerance) for f in files]
    except (OSError, ValueError) as e:
        print(f"error: {e}", file=sys.stderr)
        return 2
    found = False
    for r in results:
        found |= r["agent_agent_overlaps"] > 0 or r["agent_obstacle_overlaps"] > 0
        if args.json:
            print(json.dumps(r))
            continue
        print(
            f"{r['episode']}: {r['steps']} steps, {r['agents_seen']} agents; "
            f"agent-agent overlaps {r['agent_agent_overlaps']} (deepest {r['deepest_agent_agent_m']:.6f} m), "
            f"agent-obstacle overlaps {r['agent_obstacle_overlaps']} (deepest {r['deepest_agent_obstacle_m']:.6f} m)"
        )
        lines = [
            f"  agents {c['agents'][0]} and {c['agents'][1]}: {c['from_s']:.3f}-{c['to_s']:.3f} s, deepest {c['deepest_m']:.6f} m"
            for c in r["agent_agent"]
        ] + [
            f"  agent {c['agent']} and obstacle {c['obstacle']}: {c['from_s']:.3f}-{c['to_s']:.3f} s, deepest {c['deepest_m']:.6f} m"
            for c in r["agent_obstacle"]
        ]
        for line in lines[: args.max_lines]:
            print(line)
        if len(lines) > args.max_lines:
            print(f"  … {len(lines) - args.max_lines} more (--json lists them all)")
    return 1 if found else 0


if __name__ == "__main__":
    sys.exit(main())
