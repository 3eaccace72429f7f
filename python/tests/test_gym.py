"""The Gymnasium environments: `check_env`, determinism under `reset(seed=…)`, random rollouts."""

import time
import warnings

import gymnasium
import numpy as np
import pytest
from gymnasium.utils.env_checker import check_env

import strider.gym  # noqa: F401  (registers the environments)
from strider.gym import AnimationControlEnv, NavigateEnv

ENVS = [
    ("strider/Navigate-v0", dict(map="random:semi", body="disc")),
    ("strider/Navigate-v0", dict(map="random:rooms", body="animated", rays=16)),
    ("strider/Navigate-v0", dict(map="tests/fixtures/maps/tiny.map", body="disc")),
    ("strider/AnimationControl-v0", dict()),
]
IDS = ["navigate-disc", "navigate-animated", "navigate-movingai", "animation"]


@pytest.fixture(autouse=True)
def _in_repo(repo, monkeypatch):
    monkeypatch.chdir(repo)


@pytest.mark.parametrize("name,kw", ENVS, ids=IDS)
def test_check_env_passes_without_warnings(name, kw):
    env = gymnasium.make(name, **kw)
    # Gymnasium's conventions (actions in [-1, 1], finite observation bounds) are kept: any
    # warning of the checker fails the test.
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        check_env(env.unwrapped, skip_render_check=False)


@pytest.mark.parametrize("name,kw", [ENVS[0], ENVS[3]], ids=["navigate", "animation"])
def test_stepping_before_reset_or_after_the_end_raises(name, kw):
    env = gymnasium.make(name, **kw).unwrapped
    with pytest.raises(gymnasium.error.ResetNeeded):
        env.step(env.action_space.sample())
    env.reset(seed=1)
    env.action_space.seed(0)
    done = False
    while not done:
        _, _, terminated, truncated, _ = env.step(env.action_space.sample())
        done = terminated or truncated
    with pytest.raises(gymnasium.error.ResetNeeded):
        env.step(env.action_space.sample())
    env.reset(seed=2)
    env.step(env.action_space.sample())


def test_navigate_actions_are_shares_of_the_body_limits():
    env = NavigateEnv("random:sparse", body="disc")
    limits = env._sim.limits
    top, turn = limits["max_speed_mps"], limits["max_turn_rate_rad_s"]
    assert env.action_space.low.tolist() == [-1.0, -1.0] and env.action_space.high.tolist() == [1.0, 1.0]
    assert np.all(np.isfinite(env.observation_space.low)) and np.all(np.isfinite(env.observation_space.high))
    np.testing.assert_allclose(env.action_of(turn / 2, top), [0.5, 1.0])
    np.testing.assert_allclose(env.action_of(-10 * turn, 0.0), [-1.0, -1.0])
    np.testing.assert_allclose(env.action_of(0.0, top / 2), [0.0, 0.0])


def rollout(env, seed, steps, actions_seed=0):
    """`steps` random steps from reset(seed), resetting at episode ends; every observation and
    reward, and the steps per second."""
    env.action_space.seed(actions_seed)
    obs, _ = env.reset(seed=seed)
    trace, clock = [obs], time.perf_counter()
    for _ in range(steps):
        obs, reward, terminated, truncated, info = env.step(env.action_space.sample())
        trace.append((obs, reward, terminated, truncated))
        if terminated or truncated:
            obs, _ = env.reset()
            trace.append(obs)
    return trace, steps / (time.perf_counter() - clock)


def same(a, b):
    if isinstance(a, dict):
        return a.keys() == b.keys() and all(same(a[k], b[k]) for k in a)
    if isinstance(a, tuple):
        return len(a) == len(b) and all(same(x, y) for x, y in zip(a, b))
    return np.array_equal(a, b)


@pytest.mark.parametrize("name,kw", ENVS, ids=IDS)
def test_deterministic_under_reset_seed(name, kw):
    first, _ = rollout(gymnasium.make(name, **kw), seed=42, steps=120)
    second, _ = rollout(gymnasium.make(name, **kw), seed=42, steps=120)
    other, _ = rollout(gymnasium.make(name, **kw), seed=43, steps=120)
    assert all(same(a, b) for a, b in zip(first, second)) and len(first) == len(second)
    assert not all(same(a, b) for a, b in zip(first, other))


@pytest.mark.parametrize(
    "name,kw", [ENVS[0], ENVS[1], ENVS[3]], ids=["navigate-disc", "navigate-animated", "animation"]
)
def test_a_thousand_random_steps(name, kw, record_property):
    env = gymnasium.make(name, **kw)
    trace, rate = rollout(env, seed=7, steps=1000)
    record_property("steps_per_s", rate)
    print(f"{name} {kw}: {rate:.0f} steps/s")
    steps = [t for t in trace if isinstance(t, tuple)]
    assert len(steps) == 1000
    assert all(np.isfinite(r) for _, r, _, _ in steps)
    assert all(env.observation_space.contains(t[0]) for t in steps)


def test_navigate_rewards_progress_and_ends_at_the_goal():
    env = NavigateEnv("random:sparse", body="disc", frame_skip=4)
    obs, info = env.reset(seed=3)
    total, terminated, truncated = 0.0, False, False
    # Steer straight at the goal: the observation's bearing, as a proportional controller.
    while not (terminated or truncated):
        bearing = obs[-2]
        front = obs[0]
        obs, reward, terminated, truncated, info = env.step(env.action_of(3.0 * bearing, 1.5 if front > 0.5 else 0.3))
        total += reward
    if terminated:
        assert info["distance_m"] < 1.0 and total > 5.0
    frame = NavigateEnv("random:sparse", render_mode="rgb_array", width=64, height=48)
    frame.reset(seed=1)
    assert frame.render().shape == (48, 64, 3)


def test_nan_actions_raise():
    env = NavigateEnv("random:sparse")
    env.reset(seed=0)
    with pytest.raises(ValueError, match="finite"):
        env.step(np.array([np.nan, 1.0]))
    with pytest.raises(ValueError, match="turn rate, speed"):
        env.step(np.zeros(3))
    anim = AnimationControlEnv()
    anim.reset(seed=0)
    with pytest.raises(ValueError):
        anim.step(float("nan"))
    with pytest.raises(ValueError, match="must be in"):
        anim.step(anim.action_space.n)


def test_the_animation_mdp_masks_candidates_and_offers_sarsa():
    env = AnimationControlEnv()
    obs, info = env.reset(seed=5)
    mask = info["action_mask"]
    assert mask.shape == (env.action_space.n,) and mask[0] == 1
    assert mask[info["sarsa_action"]] == 1
    # Following strider's SARSA policy scores at least as well as random choices, on average.
    def mean_reward(pick, episodes=20):
        rewards = []
        for ep in range(episodes):
            obs, info = env.reset(seed=100 + ep)
            done = False
            while not done:
                obs, r, term, trunc, info = env.step(pick(info))
                rewards.append(r)
                done = term or trunc
        return float(np.mean(rewards))

    rng = np.random.default_rng(0)
    sarsa = mean_reward(lambda info: info["sarsa_action"])
    random = mean_reward(lambda info: int(rng.choice(np.flatnonzero(info["action_mask"]))))
    assert sarsa > random
    # A masked action plays the natural successor and says so.
    env.reset(seed=1)
    for _ in range(50):
        mask = env.action_masks()
        if not mask.all():
            _, _, _, _, info = env.step(int(np.flatnonzero(~mask)[0]))
            assert info["masked_action"]
            break
        env.step(0)
