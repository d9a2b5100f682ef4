#!/usr/bin/env python3
"""The SciPy peer of shapecast-bench-basis: the same manifold-harmonic eigenproblem solved with SciPy alone.

Measures, for each SciPy set-up, the wall time of solving S h = λ M h for the m eigenpairs nearest the shift σ
(S: the project's cotangent stiffness, M = diag(mass): its lumped mass, σ = −4π/area as manifoldHarmonicBasis()
uses), the child's peak RSS, the max relative residual and the eigenvalue agreement with the project's eigenvalues.

Input: a folder written by shapecast-bench-basis (bench/scipy_peer_problem.h):
  stiffness.mtx  S, Matrix Market coordinate real symmetric (lower triangle)
  mass.txt       the #V lumped masses, one per line
  problem.json   {"m": int, "sigma": float, "vertices": int, "reference_eigenvalues": [m floats]}

Set-ups (each runs in its own child process, so that its peak RSS is its own):
  a  eigsh(S, k=m, M=M, sigma=σ, which='LM'): SciPy's default shift-invert through SuperLU (COLAMD ordering).
  b  the same with OPinv = symmetric-mode SuperLU of S − σM (MMD on AᵀA + A, no pivoting), usually much faster.
  c  b in standard form: D S D with D = M^(−1/2) (M is diagonal), so ARPACK needs no M-inner products; h = D y.
Tried and left out (100k dragon, this machine, 2026-11-26): lobpcg(S, X, B=M, M=the symmetric-mode SuperLU solve of
S − σM, largest=False) with a block of m + 20 random vectors took 118 s for 30 iterations (then 100 pairs below
residual 1e-6) and over 1.4 GB: about 3.5 s per iteration of dense O(#V·b²) work, so even 5 iterations cost more
than b or c (about 10 s). ncv = 5m/2 (as the project's Lanczos) instead of ARPACK's default changed b and c by
under 5%.

Every set-up uses ARPACK's tolerance 1e-10 on the Ritz values (the project's Lanczos tolerance, Spectra's) and its
default ncv = max(2m + 1, 20). Timing excludes loading the files; it includes the factorisation.

Reported per set-up (one JSON line for all, on stdout):
  solve_s               wall seconds of factorisation + eigensolve (time.perf_counter)
  peak_rss_mb           resource.getrusage(RUSAGE_SELF).ru_maxrss of the child in MiB: includes Python, NumPy,
                        SciPy and the loaded matrices (loaded_rss_mb: the same just before solving)
  max_residual          max over the pairs of ‖S h − λ M h‖_{M⁻¹} / (|λ| + |σ|), as the project's
                        relativeResiduals() (src/spectral/subspace_iteration.cpp)
  orthonormality_error  max abs(HᵀMH − I)
  max_eigenvalue_diff   max over k of |λ_k − λ_k(project)| / (|λ_k(project)| + |σ|) (the same scale as the residual:
                        λ_0 = 0 once per component, so a plain relative difference is undefined)
"best" names the fastest set-up whose max_residual is below 1e-6 and max_eigenvalue_diff below 1e-6.

Usage: scipy_basis_peer.py FOLDER [--setups a,b,c] [--timeout 900]
       scipy_basis_peer.py FOLDER --setup b     (one set-up in this process: what the parent runs per child)
Standard library + NumPy + SciPy only.
"""

import argparse
import json
import os
import resource
import subprocess
import sys
import time

import numpy as np
import scipy
import scipy.io
import scipy.sparse as sp
import scipy.sparse.linalg as spla

TOLERANCE = 1e-10
ACCEPT = 1e-6


def symmetric_superlu(matrix):
    """SuperLU of a symmetric positive definite matrix in symmetric mode: no pivoting, MMD on AᵀA + A."""
    return spla.splu(matrix.tocsc(), permc_spec="MMD_AT_PLUS_A", diag_pivot_thresh=0,
                     options=dict(SymmetricMode=True))


def solve_default(S, mass, sigma, m):
    return spla.eigsh(S, k=m, M=sp.diags(mass, format="csc"), sigma=sigma, which="LM", tol=TOLERANCE)


def solve_symmetric_lu(S, mass, sigma, m):
    M = sp.diags(mass, format="csc")
    lu = symmetric_superlu(S - sigma * M)
    op_inv = spla.LinearOperator(S.shape, matvec=lu.solve, dtype=np.float64)
    return spla.eigsh(S, k=m, M=M, sigma=sigma, which="LM", OPinv=op_inv, tol=TOLERANCE)


def solve_standard_form(S, mass, sigma, m):
    d = sp.diags(1.0 / np.sqrt(mass), format="csc")
    A = (d @ S @ d).tocsc()
    lu = symmetric_superlu(A - sigma * sp.identity(A.shape[0], format="csc"))
    op_inv = spla.LinearOperator(A.shape, matvec=lu.solve, dtype=np.float64)
    values, y = spla.eigsh(A, k=m, sigma=sigma, which="LM", OPinv=op_inv, tol=TOLERANCE)
    return values, y / np.sqrt(mass)[:, None]


SETUPS = {
    "a": ("eigsh shift-invert, default SuperLU", solve_default),
    "b": ("eigsh + OPinv symmetric-mode SuperLU", solve_symmetric_lu),
    "c": ("eigsh standard form D S D + symmetric-mode SuperLU", solve_standard_form),
}


def rss_mb():
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0  # Linux: KiB


def load(folder):
    with open(os.path.join(folder, "problem.json"), encoding="utf-8") as f:
        problem = json.load(f)
    S = scipy.io.mmread(os.path.join(folder, "stiffness.mtx")).tocsc()
    mass = np.loadtxt(os.path.join(folder, "mass.txt"), dtype=np.float64)
    if S.shape != (mass.size, mass.size) or mass.size != problem["vertices"]:
        raise ValueError("stiffness, mass and problem.json disagree on #V")
    return S, mass, problem


def run_one(folder, key):
    """Loads the problem, solves it with set-up `key`, returns the figures (a dict)."""
    S, mass, problem = load(folder)
    sigma, m = float(problem["sigma"]), int(problem["m"])
    out = {"setup": key, "description": SETUPS[key][0], "loaded_rss_mb": rss_mb()}
    start = time.perf_counter()
    try:
        values, H = SETUPS[key][1](S, mass, sigma, m)
    except (spla.ArpackNoConvergence, RuntimeError, ValueError) as e:
        out["error"] = f"{type(e).__name__}: {e}"
        return out
    out["solve_s"] = time.perf_counter() - start
    out["peak_rss_mb"] = rss_mb()
    order = np.argsort(values)
    values, H = values[order], H[:, order]
    residual = S @ H - (mass[:, None] * H) * values[None, :]
    norms = np.sqrt(np.einsum("ij,ij,i->j", residual, residual, 1.0 / mass))
    out["max_residual"] = float(np.max(norms / (np.abs(values) + abs(sigma))))
    gram = H.T @ (mass[:, None] * H)
    out["orthonormality_error"] = float(np.max(np.abs(gram - np.eye(m))))
    reference = np.asarray(problem.get("reference_eigenvalues", []), dtype=np.float64)
    if reference.size == m:
        out["max_eigenvalue_diff"] = float(np.max(np.abs(values - reference) / (np.abs(reference) + abs(sigma))))
    out["first_eigenvalues"] = [float(v) for v in values[:5]]
    return out


def run_all(folder, keys, timeout):
    """Runs each set-up in a child process of this script; the one JSON summary line."""
    results = []
    for key in keys:
        try:
            child = subprocess.run([sys.executable, os.path.abspath(__file__), folder, "--setup", key],
                                   capture_output=True, text=True, timeout=timeout, check=False)
            lines = child.stdout.strip().splitlines()
            if child.returncode == 0 and lines:
                results.append(json.loads(lines[-1]))
            else:
                results.append({"setup": key, "description": SETUPS[key][0],
                                "error": f"exit {child.returncode}: {child.stderr.strip()[-300:]}"})
        except subprocess.TimeoutExpired:
            results.append({"setup": key, "description": SETUPS[key][0], "error": f"over {timeout} s"})
    for r in results:
        r["accepted"] = ("solve_s" in r and r["max_residual"] < ACCEPT
                         and r.get("max_eigenvalue_diff", 0.0) < ACCEPT)
    good = [r for r in results if r["accepted"]]
    best = min(good, key=lambda r: r["solve_s"])["setup"] if good else None
    return {"scipy": scipy.__version__, "numpy": np.__version__, "python": sys.version.split()[0],
            "openblas_num_threads": os.environ.get("OPENBLAS_NUM_THREADS", "unset"), "tolerance": TOLERANCE,
            "setups": results, "best": best}


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("folder")
    parser.add_argument("--setups", default=",".join(SETUPS), help="comma-separated set-ups (default: all)")
    parser.add_argument("--setup", choices=sorted(SETUPS), help="run one set-up in this process")
    parser.add_argument("--timeout", type=float, default=900.0, help="seconds per set-up")
    args = parser.parse_args()
    if args.setup:
        print(json.dumps(run_one(args.folder, args.setup)))
        return 0
    keys = [k for k in args.setups.split(",") if k]
    unknown = [k for k in keys if k not in SETUPS]
    if unknown:
        parser.error(f"unknown set-ups {unknown}; known: {sorted(SETUPS)}")
    print(json.dumps(run_all(args.folder, keys, args.timeout)))
    return 0


if __name__ == "__main__":
    sys.exit(main())
