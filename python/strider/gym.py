"""Gymnasium environments, registered on import:

- ``strider/Navigate-v0``: the navigation task (the fuzzy + RL paper's §3.1) driven by the
  agent. The observation is the range scan around the agent (``rays`` free distances from
  straight ahead counter-clockwise, metres, at most the sensor's range) followed by the goal's
  distance (m, capped at ``max_goal_distance``) and bearing (rad, positive to the left) and the
  agent's speed (m/s, capped at twice the commanded maximum): every bound finite. The action
  is two numbers in [-1, 1], as Gymnasium recommends: the turn rate as a share of the body's
  largest (-1 full right, 1 full left) and the speed from standing (-1) to the body's top
  speed (1), what the fuzzy planner would command (:meth:`NavigateEnv.action_of` turns rad/s
  and m/s into one). The reward is the progress toward the goal less penalties for
  collisions, stalls (steps the body refused or shortened against an obstacle) and time, plus
  a bonus at the goal. ``terminated`` at the goal, ``truncated`` at the task's time limit.
- ``strider/AnimationControl-v0``: the RL animation controller's MDP (the paper's §3.2): at each
  switch point choose the next interval among the candidates (``Discrete``; candidates past
  the interval's own are masked in ``info["action_mask"]`` and ``action_masks()`` and play the
  natural successor); the observation is the state strider's SARSA policy sees (the interval
  playing, the speed and direction errors), the reward Eq. 4; ``info["sarsa_action"]`` is what
  strider's trained policy would choose.

Both are deterministic under ``reset(seed=…)``, and both raise ``gymnasium.error.ResetNeeded``
when stepped before ``reset`` or after their episode ended.
"""

from __future__ import annotations

import math
import os
from typing import Any, Optional, Tuple, Union

import gymnasium
import numpy as np
from gymnasium import spaces

from . import _strider, episode_count

__all__ = ["NavigateEnv", "AnimationControlEnv"]

# The agent's speed in the observation is capped at this many times the commanded maximum (the
# animated character's clips may briefly play faster than commanded).
SPEED_BOUND = 2.0

PathLike = Union[str, "os.PathLike[str]"]


class NavigateEnv(gymnasium.Env):
    """Drive a strider agent to its goal.

    Args:
        map: as for :func:`strider.run` (default ``"random:semi"``: a new seeded world per
            episode).
        body: ``"disc"`` (default) or ``"animated"``.
        rules: the navigation rules of the world's other agents, if any (the driven agent
            ignores them).
        scen: a MovingAI scenario file; each reset picks one of its tasks.
        rays: rays of the range scan in the observation.
        max_goal_distance: the goal's distance in the observation is capped here (metres; its
            bound, so that every bound is finite).
        frame_skip: simulation steps (0.05 s each) per environment step.
        progress_weight, collision_penalty, stall_penalty, time_penalty, goal_bonus: the
            reward's terms (per metre, per collision, per stalled step, per second, once).
        render_mode: ``"rgb_array"`` or ``None``; ``width`` and ``height`` size the frames.
    """

    metadata = {"render_modes": ["rgb_array"], "render_fps": 5}

    def __init__(
        self,
        map: PathLike = "random:semi",
        *,
        body: str = "disc",
        rules: Optional[PathLike] = None,
        scen: Optional[PathLike] = None,
        rays: int = 32,
        max_goal_distance: float = 1000.0,
        frame_skip: int = 4,
        progress_weight: float = 1.0,
        collision_penalty: float = 1.0,
        stall_penalty: float = 0.05,
        time_penalty: float = 0.01,
        goal_bonus: float = 10.0,
        render_mode: Optional[str] = None,
        width: int = 480,
        height: int = 480,
    ) -> None:
        if render_mode not in (None, "rgb_array"):
            raise ValueError(f"render_mode must be None or 'rgb_array', found {render_mode!r}")
        if not 1 <= int(rays) <= 4096:
            raise ValueError(f"rays must be in 1..=4096, found {rays}")
        if int(frame_skip) < 1:
            raise ValueError(f"frame_skip must be at least 1, found {frame_skip}")
        if not (math.isfinite(max_goal_distance) and max_goal_distance > 0):
            raise ValueError(f"max_goal_distance must be a positive number of metres, found {max_goal_distance}")
        fspath = lambda p: None if p is None else os.fspath(p)  # noqa: E731
        self._map = os.fspath(map)
        self._sim = _strider.Simulation(self._map, body=body, rules=fspath(rules), scen=fspath(scen))
        self._tasks = 1 if self._map.startswith("random:") else episode_count(self._map, scen=fspath(scen))
        self.rays, self.frame_skip = int(rays), int(frame_skip)
        self.weights = (progress_weight, collision_penalty, stall_penalty, time_penalty, goal_bonus)
        self.render_mode, self.width, self.height = render_mode, int(width), int(height)
        limits = self._sim.limits
        self._range = float(limits["range_m"])
        self._max_turn, self._max_speed = float(limits["max_turn_rate_rad_s"]), float(limits["max_speed_mps"])
        low = np.concatenate([np.zeros(self.rays), [0.0, -math.pi, 0.0]]).astype(np.float32)
        high = np.concatenate(
            [np.full(self.rays, self._range), [float(max_goal_distance), math.pi, SPEED_BOUND * self._max_speed]]
        ).astype(np.float32)
        self.observation_space = spaces.Box(low, high, dtype=np.float32)
        self.action_space = spaces.Box(-1.0, 1.0, shape=(2,), dtype=np.float32)
        self._distance = 0.0
        self._counts = (0, 0)
        self._running = False

    def action_of(self, turn_rate: float, speed: float) -> np.ndarray:
        """The action that commands `turn_rate` (rad/s, positive to the left) and `speed` (m/s),
        within the body's limits."""
        turn = np.clip(turn_rate / self._max_turn, -1.0, 1.0)
        forward = np.clip(2.0 * speed / self._max_speed - 1.0, -1.0, 1.0)
        return np.array([turn, forward], dtype=np.float32)

    def _goal(self) -> Tuple[float, float]:
        (x, y), h = self._sim.positions[0], self._sim.headings[0]
        gx, gy = self._sim.goals[0]
        bearing = math.atan2(gy - y, gx - x) - h
        bearing = (bearing + math.pi) % (2 * math.pi) - math.pi
        return math.hypot(gx - x, gy - y), bearing

    def _observation(self) -> np.ndarray:
        distance, bearing = self._goal()
        scan = self._sim.range_scan(self.rays)
        obs = np.concatenate([scan, [distance, bearing, self._sim.speeds[0]]]).astype(np.float32)
        return np.clip(obs, self.observation_space.low, self.observation_space.high)

    def _info(self) -> dict:
        m = self._sim.metrics[0]
        return {
            "episode": self._sim.episode,
            "seed": self._sim.seed,
            "time_s": self._sim.time_s,
            "distance_m": self._goal()[0],
            "collisions": m["collisions"],
            "stalls": m["stalls"],
            "path_length_m": m["path_length_m"],
        }

    def reset(self, *, seed: Optional[int] = None, options: Optional[dict] = None) -> Tuple[np.ndarray, dict]:
        super().reset(seed=seed)
        run_seed = int(self.np_random.integers(0, 2**63 - 1))
        episode = int(self.np_random.integers(0, self._tasks))
        self._sim.reset(episode=episode, seed=run_seed)
        self._distance = self._goal()[0]
        m = self._sim.metrics[0]
        self._counts = (m["collisions"], m["stalls"])
        self._running = True
        return self._observation(), self._info()

    def step(self, action: Any) -> Tuple[np.ndarray, float, bool, bool, dict]:
        if not self._running:
            raise gymnasium.error.ResetNeeded("call reset() before step(), and again once an episode has ended")
        a = np.asarray(action, dtype=np.float64).reshape(-1)
        if a.shape != (2,):
            raise ValueError(f"an action is (turn rate, speed), found shape {np.shape(action)}")
        if not np.all(np.isfinite(a)):
            raise ValueError(f"an action must be finite, found {a.tolist()}")
        a = np.clip(a, -1.0, 1.0)
        turn = float(a[0]) * self._max_turn
        speed = (float(a[1]) + 1.0) / 2.0 * self._max_speed
        before = self._sim.time_s
        self._sim.drive(turn, speed)
        self._sim.step(self.frame_skip)
        distance = self._goal()[0]
        m = self._sim.metrics[0]
        collisions, stalls = m["collisions"] - self._counts[0], m["stalls"] - self._counts[1]
        self._counts = (m["collisions"], m["stalls"])
        outcome = self._sim.outcomes[0]
        w_progress, w_collision, w_stall, w_time, bonus = self.weights
        reward = (
            w_progress * (self._distance - distance)
            - w_collision * collisions
            - w_stall * stalls
            - w_time * (self._sim.time_s - before)
            + (bonus if outcome == "reached" else 0.0)
        )
        self._distance = distance
        # A refused episode (no way round for the body) ends as a terminal state, not a truncation.
        terminated = outcome in ("reached", "refused")
        truncated = outcome == "timed_out"
        self._running = not (terminated or truncated)
        return self._observation(), float(reward), terminated, truncated, self._info()

    def render(self) -> Optional[np.ndarray]:
        if self.render_mode == "rgb_array":
            return self._sim.frame(self.width, self.height)
        return None


class AnimationControlEnv(gymnasium.Env):
    """Choose the next animation interval at each switch point (the fuzzy + RL paper's §3.2).

    Args:
        db: an animation database directory (default: built in).
        policy: its trained policy file (default: the shipped one); gives ``sarsa_action`` and
            the reward's α, β and tolerances.
        episode_length: switch points per episode (default: training's, 24).
    """

    metadata = {"render_modes": []}

    def __init__(
        self,
        *,
        db: Optional[PathLike] = None,
        policy: Optional[PathLike] = None,
        episode_length: Optional[int] = None,
    ) -> None:
        fspath = lambda p: None if p is None else os.fspath(p)  # noqa: E731
        self._mdp = _strider.AnimationMdp(fspath(db), fspath(policy))
        self.episode_length = int(episode_length or self._mdp.episode_length)
        if self.episode_length < 1:
            raise ValueError(f"episode_length must be at least 1, found {episode_length}")
        bound = self._mdp.speed_bound
        self.observation_space = spaces.Dict(
            {
                "interval": spaces.Discrete(self._mdp.intervals),
                "errors": spaces.Box(
                    np.array([-bound, -math.pi], dtype=np.float32),
                    np.array([bound, math.pi], dtype=np.float32),
                    dtype=np.float32,
                ),
            }
        )
        self.action_space = spaces.Discrete(self._mdp.max_actions)
        self._t = 0
        self._running = False

    def _observation(self) -> dict:
        interval, speed_error, direction_error = self._mdp.state()
        errors = np.array([speed_error, direction_error], dtype=np.float32)
        box = self.observation_space["errors"]
        return {"interval": int(interval), "errors": np.clip(errors, box.low, box.high)}

    def action_masks(self) -> np.ndarray:
        """The candidates of the interval playing (for maskable algorithms)."""
        return np.array(self._mdp.action_mask(), dtype=bool)

    def _info(self, masked: bool = False) -> dict:
        turn_rate, speed = self._mdp.task()
        return {
            "action_mask": self.action_masks().astype(np.int8),
            "masked_action": masked,
            "sarsa_action": self._mdp.sarsa_action(),
            "task_turn_rate": turn_rate,
            "task_speed": speed,
        }

    def reset(self, *, seed: Optional[int] = None, options: Optional[dict] = None) -> Tuple[dict, dict]:
        super().reset(seed=seed)
        self._mdp.reset(int(self.np_random.integers(0, 2**63 - 1)))
        self._t = 0
        self._running = True
        return self._observation(), self._info()

    def step(self, action: Any) -> Tuple[dict, float, bool, bool, dict]:
        if not self._running:
            raise gymnasium.error.ResetNeeded("call reset() before step(), and again once an episode has ended")
        value = np.asarray(action)
        if value.shape not in ((), (1,)) or not np.issubdtype(value.dtype, np.number):
            raise ValueError(f"an action is one candidate index, found {action!r}")
        if not np.isfinite(value).all() or value.reshape(()) != np.floor(value.reshape(())):
            raise ValueError(f"an action is a whole candidate index, found {action!r}")
        a = int(value.reshape(()))
        if not self.action_space.contains(a):
            raise ValueError(f"action must be in 0..{self.action_space.n - 1}, found {a}")
        reward, masked = self._mdp.step(a)
        self._t += 1
        truncated = self._t >= self.episode_length
        self._running = not truncated
        return self._observation(), float(reward), False, truncated, self._info(masked)


def _register() -> None:
    for name, entry in (("strider/Navigate-v0", NavigateEnv), ("strider/AnimationControl-v0", AnimationControlEnv)):
        if name not in gymnasium.registry:
            gymnasium.register(id=name, entry_point=f"{__name__}:{entry.__name__}")


_register()
