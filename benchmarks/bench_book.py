"""Benchmark: the example book built with ``--jobs 1`` and ``--jobs 2``, cold and warm plan cache.

Run: ``python3 benchmarks/bench_book.py [--config configs/book.yaml] [--jobs 1 2] [--repeat 1]``

Each build is a fresh ``python -m h2s_print.cli -q build CONFIG -o DIR --jobs N`` process, timed
by wall clock (interpreter start and imports included, as a user sees it).  *cold*: a new, empty
output folder (every plan solved); *warm*: the same command again on that folder (every plan
from ``DIR/.h2s-cache``).  With ``--repeat R`` the best of R runs is shown.  The last column
checks that the book PDF is byte-identical to the first build's.

The project's modules run from compiled bytecode, as an installed package's do: they are
compiled once before the first build (``__pycache__`` beside the sources, ignored by git)
and the builds run without ``PYTHONDONTWRITEBYTECODE``, so that no build pays for compiling
the sources (about 0.15 s a process on this machine).
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]


def bytecode_env() -> dict[str, str]:
    """The environment of the builds: the repository first on the path, bytecode read and
    written (module docstring)."""
    env = {k: v for k, v in os.environ.items() if k != "PYTHONDONTWRITEBYTECODE"}
    env["PYTHONPATH"] = str(REPO) + os.pathsep + os.environ.get("PYTHONPATH", "")
    return env


def build_seconds(config: Path, out: Path, jobs: int, env: dict[str, str]) -> float:
    """Wall-clock seconds of one ``h2s build`` process (raises when it fails)."""
    cmd = [sys.executable, "-m", "h2s_print.cli", "-q", "build", str(config), "-o", str(out),
           "--jobs", str(jobs)]
    start = time.perf_counter()
    proc = subprocess.run(cmd, capture_output=True, text=True, cwd=REPO, env=env)
    seconds = time.perf_counter() - start
    if proc.returncode != 0:
        raise SystemExit(f"build failed ({proc.returncode}):\n{proc.stderr}")
    return seconds


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--config", type=Path, default=REPO / "configs" / "book.yaml")
    parser.add_argument("--jobs", type=int, nargs="+", default=[1, 2])
    parser.add_argument("--repeat", type=int, default=1)
    args = parser.parse_args()
    config = args.config.resolve()
    name = config.stem
    print(f"{config.relative_to(REPO) if config.is_relative_to(REPO) else config}, "
          f"{os.cpu_count()} CPUs, Python {sys.version.split()[0]}")
    print(f"{'jobs':>4}  {'cache':<5}  {'seconds':>8}  {'PDF bytes':>10}  identical")
    reference: bytes | None = None
    with tempfile.TemporaryDirectory(prefix="bench_book.") as tmp:
        env = bytecode_env()
        subprocess.run([sys.executable, "-m", "compileall", "-q", str(REPO / "h2s_print")],
                       check=True, env=env, capture_output=True)
        for jobs in args.jobs:
            best = {"cold": float("inf"), "warm": float("inf")}
            for r in range(args.repeat):
                out = Path(tmp) / f"j{jobs}-{r}"
                best["cold"] = min(best["cold"], build_seconds(config, out, jobs, env))
                best["warm"] = min(best["warm"], build_seconds(config, out, jobs, env))
            pdf = (out / name / f"{name}.pdf").read_bytes()
            reference = pdf if reference is None else reference
            for kind in ("cold", "warm"):
                print(f"{jobs:>4}  {kind:<5}  {best[kind]:8.2f}  {len(pdf):>10}  "
                      f"{'yes' if pdf == reference else 'NO'}")


if __name__ == "__main__":
    main()
