"""Green on any machine (issue 32): the main job leaves a checkout clean, and the committed results agree with a
fresh run, under two other numeric kernels than this machine's own (which the rest of the suite runs on).

numpy picks its SIMD kernels at import from the CPU (``NPY_DISABLE_CPU_FEATURES`` switches dispatch targets
off) and OpenBLAS its BLAS kernel (``OPENBLAS_CORETYPE``).  Two other kernels are run in subprocesses:

- (a) numpy without its AVX-512 family, OpenBLAS's Haswell kernel (AVX2/FMA3);
- (b) numpy without AVX2, FMA3 and AVX-512, OpenBLAS's Sandybridge kernel (AVX).

numpy refuses to disable a target the build requires as its baseline, and a target the CPU lacks is already
off, so the lists are computed from numpy's own ``__cpu_dispatch__`` and ``__cpu_features__``; an OpenBLAS kernel
the CPU cannot run is not requested.  Each subprocess prints, and the test checks, which kernels actually ran.
"""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from designer.report.agreement import compare_folders

ROOT = Path(__file__).resolve().parents[2]

AVX512 = ("AVX512", "X86_V4")
"""numpy dispatch targets of the AVX-512 family: AVX512F, AVX512_SKX, AVX512_ICL ... and x86-64-v4 (numpy >= 2.4)."""
AVX2_FMA3 = ("AVX2", "FMA3", "X86_V3")
"""numpy dispatch targets of AVX2 and FMA3: AVX2, FMA3 and x86-64-v3 (numpy >= 2.4)."""

PROBE = r"""
import ctypes, json, sys
from numpy._core._multiarray_umath import __cpu_dispatch__, __cpu_features__
import scipy.linalg  # loads scipy's OpenBLAS too
cores = {}
for lib in sorted({l.split()[-1] for l in open("/proc/self/maps") if "openblas" in l.lower() and l.split()[-1].startswith("/")}):
    handle = ctypes.CDLL(lib)
    for name in ("openblas_get_corename", "scipy_openblas_get_corename", "scipy_openblas_get_corename64_",
                 "openblas_get_corename64_", "scipy_openblas64_get_corename"):
        fn = getattr(handle, name, None)
        if fn is not None:
            fn.restype = ctypes.c_char_p
            cores[lib.rsplit("/", 1)[-1]] = fn().decode()
            break
print(json.dumps({"numpy": [t for t in __cpu_dispatch__ if __cpu_features__.get(t)], "openblas": cores}))
"""
"""Prints the numpy dispatch targets in use and each loaded OpenBLAS's kernel (as threadpoolctl reads it)."""

JOB = r"""
import json, sys
from designer.cli import main
from designer.report.agreement import compare_folders
codes = [main(["pareto", "--all", "problems"]), main(["pareto", "--all", "problems", "--out", sys.argv[1]])]
moved = {p: json.load(open(f"results/{p}/run.json"))["moved"] for p in sys.argv[2:]}
print(json.dumps({"codes": codes, "moved": moved}))
"""
"""The main job in the checkout (README), then the results test's run into a fresh folder."""


def _targets(families: tuple[str, ...]) -> list[str]:
    """numpy's dispatch targets of ``families`` that this CPU has (those numpy can switch off)."""
    from numpy._core._multiarray_umath import __cpu_dispatch__, __cpu_features__

    return [t for t in __cpu_dispatch__ if __cpu_features__.get(t) and t.startswith(families)]


def _has(*features: str) -> bool:
    from numpy._core._multiarray_umath import __cpu_features__

    return all(__cpu_features__.get(f) for f in features)


KERNELS = {
    "no-avx512-haswell": (AVX512, "Haswell", ("AVX2", "FMA3")),
    "no-avx2-sandybridge": (AVX512 + AVX2_FMA3, "Sandybridge", ("AVX",)),
}
"""name: (numpy families switched off, OpenBLAS kernel, the CPU features that kernel needs)."""


def _env(kernel: str) -> tuple[dict, list[str], str | None]:
    families, core, needs = KERNELS[kernel]
    env = {k: v for k, v in os.environ.items() if not k.startswith(("NPY_", "OPENBLAS_"))}
    off = _targets(families)
    env["NPY_DISABLE_CPU_FEATURES"] = " ".join(off)
    core = core if _has(*needs) else None  # a kernel the CPU cannot run would stop the process
    if core is not None:
        env["OPENBLAS_CORETYPE"] = core
    return env, off, core


def _checkout(tmp: Path) -> Path:
    """A git repository holding a copy of problems/, results/ (run.json aside) and .gitignore, committed."""
    repo = tmp / "checkout"
    shutil.copytree(ROOT / "problems", repo / "problems")
    shutil.copytree(ROOT / "results", repo / "results", ignore=shutil.ignore_patterns("run.json"))
    shutil.copy(ROOT / ".gitignore", repo / ".gitignore")
    for args in (["init", "-q"], ["add", "-A"], ["commit", "-q", "-m", "checkout"]):
        _git(repo, *args)
    return repo


def _git(repo: Path, *args: str) -> str:
    config = ["-c", "user.name=test", "-c", "user.email=test@example.invalid", "-c", "commit.gpgsign=false"]
    return subprocess.run(["git", *config, *args], cwd=repo, capture_output=True, text=True, check=True).stdout


@pytest.mark.parametrize("kernel", list(KERNELS))
def test_main_job_under_another_numeric_kernel(kernel, tmp_path):
    """Under kernel (a) or (b): the kernels asked for are the ones that ran (numpy's targets off, OpenBLAS's core),
    `designer pareto --all problems` exits 0 and leaves the checkout clean (`git status --porcelain` empty, no
    file rewritten: run.json's ``moved`` empty), and a fresh run agrees with the committed results by number."""
    env, off, core = _env(kernel)
    probe = subprocess.run([sys.executable, "-c", PROBE], env=env, capture_output=True, text=True, check=True)
    ran = json.loads(probe.stdout)
    print(f"{kernel}: NPY_DISABLE_CPU_FEATURES={off} OPENBLAS_CORETYPE={core}; ran: {ran}")
    assert not set(off) & set(ran["numpy"]), ran
    assert ran["openblas"], "no OpenBLAS found in the process"
    if core is not None:
        assert {c.lower() for c in ran["openblas"].values()} == {core.lower()}, ran

    repo = _checkout(tmp_path)
    problems = sorted(p.stem for p in (repo / "problems").glob("*.toml"))
    fresh = tmp_path / "fresh"
    job = subprocess.run(
        [sys.executable, "-c", JOB, str(fresh), *problems], cwd=repo, env=env, capture_output=True, text=True
    )
    assert job.returncode == 0, job.stderr[-2000:]
    result = json.loads(job.stdout.strip().splitlines()[-1])
    assert result["codes"] == [0, 0]
    assert result["moved"] == {p: {} for p in problems}
    assert _git(repo, "status", "--porcelain", "--untracked-files=all") == ""
    stale = {p: compare_folders(ROOT / "results" / p, fresh / p) for p in problems}
    assert not {p: m for p, m in stale.items() if m}, stale
