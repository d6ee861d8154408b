"""MOP follower soak: one follower stepped through many performances separated by rests.

The long-run counterpart of tests/mop/test_follower.py's run: after ``--steps`` samples (default
200,000, about 1.9 hours of input at 30 Hz) every progress and log-likelihood is finite, the
forward probabilities still sum to 1, and the progress of the last performances is as accurate
as the first. Prints one JSON line last: the steps, the progress RMSE of the first and last 20
performances (median / max), the largest deviation of the probabilities' sum from 1, and the
microseconds per step.

    .venv/bin/python bench/mop_soak.py [--steps N]
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import tabletop  # noqa: E402,F401  (one BLAS thread, as the loop runs, set before numpy loads)
import numpy as np  # noqa: E402

from bench.common import emit  # noqa: E402
from bench.synthetic_actions import perform, template, warped_phase  # noqa: E402
from behaviors.mop.follower import ActionFollower  # noqa: E402


def soak(steps: int, seed: int = 13) -> dict[str, float]:
    """Step one follower of one template (120 samples, 3 features) through rests of 10 samples
    and warped, noisy performances until ``steps`` samples; returns the figures."""
    rng = np.random.default_rng(seed)
    tpl = template(rng, 120, 3)
    f = ActionFollower({"a": tpl})
    done, errors, finite, worst_sum = 0, [], True, 0.0
    t0 = time.process_time()
    while done < steps:
        rest = tpl[0] + rng.normal(0.0, 0.05, (10, 3)) * tpl.std(axis=0)
        phase = warped_phase(rng, len(tpl))
        perf = perform(rng, tpl, phase, 0.1)
        for x in rest:
            f.step(x)
        prog = np.empty(len(perf))
        for i, x in enumerate(perf):
            s = f.step(x)
            prog[i] = s.progress
            finite &= bool(np.isfinite(s.progress) and np.isfinite(s.loglik))
        done += len(rest) + len(perf)
        worst_sum = max(worst_sum, abs(float(f.forward.alpha.sum()) - 1.0))
        m = len(perf) // 5
        errors.append(float(np.sqrt(np.mean((prog[m:] - phase[m:] / (len(tpl) - 1)) ** 2))))
    cpu = time.process_time() - t0
    first, last = np.array(errors[:20]), np.array(errors[-20:])
    return {"steps": done, "performances": len(errors), "all_finite": finite,
            "first20_rmse_median": float(np.median(first)), "first20_rmse_max": float(first.max()),
            "last20_rmse_median": float(np.median(last)), "last20_rmse_max": float(last.max()),
            "alpha_sum_deviation_max": worst_sum, "us_per_step_cpu": 1e6 * cpu / done}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--steps", type=int, default=200_000,
                        help="samples to step (default 200000)")
    args = parser.parse_args()
    if args.steps <= 0:
        parser.error(f"--steps {args.steps}: must be a positive number of samples")
    figures = soak(args.steps)
    print(f"{figures['steps']} steps: last 20 performances' progress RMSE median "
          f"{figures['last20_rmse_median']:.4f}, max {figures['last20_rmse_max']:.4f}")
    emit("mop_soak", figures, {"last20_rmse_max": 0.05, "last20_rmse_median": 0.03,
                               "alpha_sum_deviation_max": 1e-9})


if __name__ == "__main__":
    main()
