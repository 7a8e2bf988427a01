"""Train a PPO policy (Stable-Baselines3) on neurov/Tracking-v0 and compare it
with the scenario's own controller (the paper's NN controller for paper_fig3)
on the same scenario and seed. Optional: needs `pip install stable-baselines3`
(and PyTorch); not run in CI.

    python examples/train_ppo.py [--scenario paper_fig3] [--timesteps 50000] [--seed 0] [--envs K]
        [--minutes M] [--eval-every S] [--eval-seed N] [--noise] [--n-steps N] [--curve c.csv] [--plot c.png]

--envs K trains on K envs of one neurov.gym.TrackingVectorEnv (through
neurov.gym.sb3.TrackingSB3VecEnv); the evaluation is the single env either way.
--minutes stops after M minutes of training wall time (evaluations not
counted); --eval-every S evaluates the deterministic policy every S s of it.
--noise adds the measurement noise of nerov_square_disturbed to the scenario.

Prints the training steps per second, the seconds spent collecting rollouts
(env steps and policy inference) and in PPO's updates, and the RMS position
error over the run of the trained policy and of the scenario's controller.
"""

from __future__ import annotations

import argparse
import csv
import time

import gymnasium
import numpy as np

import neurov
import neurov.gym  # noqa: F401  (registers neurov/Tracking-v0)
from neurov.gym import resolve_scenario

CURVE_COLUMNS = ["train_s", "timesteps", "steps_per_s", "policy_rms_m", "nn_rms_m", "rollout_s", "update_s"]


def evaluate(env: gymnasium.Env, policy, seed: int) -> tuple[float, float, int, str]:
    """Return, RMS position error [m], steps and how the episode ended."""
    obs, info = env.reset(seed=seed)
    total, errors = 0.0, []
    while True:
        obs, reward, terminated, truncated, info = env.step(policy(obs))
        total += reward
        errors.append(np.sum((info["eta_true"][:3] - info["eta_d"][:3]) ** 2))
        if terminated or truncated:
            return total, float(np.sqrt(np.mean(errors))), len(errors), "terminated" if terminated else "truncated"


def with_noise(scenario):
    """The scenario with the measurement noise of the shipped disturbed
    scenarios (one set of standard deviations for the whole project)."""
    noisy = resolve_scenario("nerov_square_disturbed")
    return scenario.replace(noise_eta=noisy.noise_eta, noise_nu=noisy.noise_nu)


def make_clock(budget_s: float | None, eval_every: float | None, evaluate_now):
    """An SB3 callback that keeps the training clock (wall time less the
    evaluations), splits it into rollout collection and PPO's updates, stops
    after `budget_s` and calls `evaluate_now(clock)` every `eval_every` s."""
    from stable_baselines3.common.callbacks import BaseCallback

    class Clock(BaseCallback):
        def _on_training_start(self) -> None:
            self.t0, self.paused, self.rollout_s, self.update_s = time.perf_counter(), 0.0, 0.0, 0.0
            self.mark, self.in_rollout, self.next_eval = self.t0, False, eval_every

        def train_s(self) -> float:
            return time.perf_counter() - self.t0 - self.paused

        def _lap(self, in_rollout: bool) -> None:
            # The time since the last mark goes to the phase that ran (evaluations move the mark).
            now = time.perf_counter()
            if self.in_rollout:
                self.rollout_s += now - self.mark
            else:
                self.update_s += now - self.mark  # PPO's update, or the setup before the first rollout
            self.mark, self.in_rollout = now, in_rollout

        def _on_rollout_start(self) -> None:
            self._lap(True)

        def _on_rollout_end(self) -> None:
            self._lap(False)

        def _on_training_end(self) -> None:
            self._lap(False)

        def _on_step(self) -> bool:
            t = self.train_s()
            if self.next_eval is not None and t >= self.next_eval:
                self._lap(self.in_rollout)
                start = time.perf_counter()
                evaluate_now(self)
                self.paused += time.perf_counter() - start
                self.mark = time.perf_counter()
                self.next_eval += eval_every
            return budget_s is None or t < budget_s

    return Clock()


def positive(kind, zero: bool = False):
    """An argparse type: a number of `kind` > 0 (>= 0 with `zero`)."""
    def parse(text: str):
        if not (kind(text) >= 0 if zero else kind(text) > 0):
            raise argparse.ArgumentTypeError(f"expected a number {'>=' if zero else '>'} 0, got {text!r}")
        return kind(text)

    parse.__name__ = kind.__name__  # argparse names it in "invalid int value"
    return parse


def main() -> None:
    import torch
    from stable_baselines3 import PPO

    from neurov.gym.sb3 import TrackingSB3VecEnv

    torch.set_num_threads(1)  # a 64-unit MLP: more threads only contend

    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--scenario", default="paper_fig3")
    p.add_argument("--timesteps", type=positive(int), help="training steps (default 50,000 without --minutes)")
    p.add_argument("--minutes", type=positive(float), help="training wall-time budget [min]")
    p.add_argument("--eval-every", type=positive(float), help="evaluate every S seconds of training")
    p.add_argument("--noise", action="store_true", help="add nerov_square_disturbed's measurement noise")
    p.add_argument("--n-steps", type=positive(int), default=2048, help="PPO's rollout steps per env")
    p.add_argument("--seed", type=int, default=0, help="PPO's seed")
    p.add_argument("--eval-seed", type=positive(int, zero=True), help="evaluations' noise seed (default: scenario's)")
    p.add_argument("--save", help="save the trained model here (.zip)")
    p.add_argument("--envs", type=positive(int, zero=True), default=0, help="vector env's envs (0: the single env)")
    p.add_argument("--curve", help="write the evaluations here (.csv)")
    p.add_argument("--plot", help="plot the evaluations' RMS against training time here (.png)")
    args = p.parse_args()
    if (args.curve or args.plot) and not args.eval_every:
        p.error("arguments --curve and --plot need --eval-every")
    timesteps = args.timesteps or (50_000 if args.minutes is None else 2**62)

    scenario = with_noise(resolve_scenario(args.scenario)) if args.noise else resolve_scenario(args.scenario)
    train_env = (TrackingSB3VecEnv(args.envs, scenario=scenario) if args.envs
                 else gymnasium.make("neurov/Tracking-v0", scenario=scenario))
    model = PPO("MlpPolicy", train_env, n_steps=args.n_steps, seed=args.seed, verbose=0, device="cpu")

    # Evaluated on an env of its own (training's episodes go on) with the
    # evaluation's noise seed, so the scenario's controller sees the same noise.
    scenario = scenario if args.eval_seed is None else scenario.replace(seed=args.eval_seed)
    nn_rms = neurov.simulate(scenario).metrics(after=0.0)["rmse_position_m"]
    eval_env = gymnasium.make("neurov/Tracking-v0", scenario=scenario)
    policy = lambda o: model.predict(o, deterministic=True)[0]  # noqa: E731
    rows: list[list[float]] = []

    def evaluate_now(clock) -> None:
        t, n = clock.train_s(), model.num_timesteps
        rms = evaluate(eval_env, policy, scenario.seed)[1]
        rows.append([t, n, n / t, rms, nn_rms, clock.rollout_s, clock.update_s])
        print(f"  {t:6.0f} s  {n:9d} steps  {n / t:7.0f} steps/s  RMS {rms:.3f} m", flush=True)

    clock = make_clock(None if args.minutes is None else 60.0 * args.minutes, args.eval_every, evaluate_now)
    model.learn(total_timesteps=timesteps, callback=clock)
    t = clock.train_s()
    print(f"PPO: {model.num_timesteps} timesteps in {t:.0f} s of training: {model.num_timesteps / t:.0f} steps/s "
          f"(rollouts {clock.rollout_s:.0f} s, updates {clock.update_s:.0f} s)")
    if args.save:
        model.save(args.save)

    ret, rms, steps, end = evaluate(eval_env, policy, scenario.seed)
    print(f"PPO policy: RMS position error over the run {rms:.3f} m ({steps} steps, {end}; return {ret:.1f})")
    print(f"the scenario's controller ({scenario.controller.type}): RMS position error over the run "
          f"{nn_rms:.3f} m (neurov.simulate)")
    if args.eval_every and rows[-1][1] != model.num_timesteps:  # the final policy closes the curve
        rows.append([t, model.num_timesteps, model.num_timesteps / t, rms, nn_rms, clock.rollout_s, clock.update_s])
    if args.curve:
        with open(args.curve, "w", newline="") as f:
            csv.writer(f).writerows([CURVE_COLUMNS, *rows])
    if args.plot:
        plot(rows, args.plot, f"{scenario.name}{' with noise' if args.noise else ''}, "
             f"{args.envs or 1} env{'s' if args.envs else ''}")


def plot(rows: list[list[float]], path: str, title: str) -> None:
    import matplotlib

    matplotlib.use("Agg")  # a file, no display
    import matplotlib.pyplot as plt

    data = np.asarray(rows)
    fig, ax = plt.subplots(figsize=(6, 3.5), dpi=100)
    ax.semilogy(data[:, 0], data[:, 3], "o-", label="PPO, deterministic policy")
    ax.axhline(data[0, 4], color="k", ls="--", label="NN controller")
    ax.set(xlabel="training time [s]", ylabel="RMS position error [m]", title=title)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend()
    fig.tight_layout()
    fig.savefig(path)


if __name__ == "__main__":
    main()
