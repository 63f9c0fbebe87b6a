"""The friction magnitudes: x = c·|R₀ + Σⱼ xⱼ·dⱼ·B_j| per sample (docs/forces.md#friction).

Equation. Element k (a pin's friction circle c = μ·r, a slide's c = μ) carries the reaction
R_k = R₀_k + Σⱼ xⱼ·dⱼ·B_jk (route 2 is linear in the loads: R₀ the frictionless solve, B_jk the
response of carrier k to element j's unit load, dⱼ = ±1 its direction), and x_k = c_k·|R_k|.

Newton, read as a fixed direction. With u_k = R_k/|R_k| the unit direction of the reaction at the
current x, |R_k| = Re(ū_k·R_k) exactly, so the Newton step of F(x) = x − c·|R(x)| is the linear
system of the reactions' directions held:

    (I − diag(c)·G)·x⁺ = c·Re(ū·R₀),   G_kj = dⱼ·Re(ū_k·B_jk) = ∂|R_k|/∂xⱼ

(an error δ in the directions leaves an error O(δ²) in |R|: quadratic). Started from the
frictionless reactions' directions (x = 0) it reaches the round-off in two or three steps at the
usual gains c·|B| ≈ 0.1 — against a dozen fixed-point sweeps. Vectorised over the samples: the
a × a system (a: the elements whose friction moves some reaction) is eliminated on whole (n,)
columns, without pivoting (I − c·G is diagonally dominant while the gain is below 1; a sample
where it is not goes to the fallback). From the second step on, a Gauss–Seidel sweep
x_k ← c_k·|R_k| checks it: a sample whose x moves there by more than CONVERGED·max|x| (a few
ulps) after FAST_STEPS is solved by :func:`newton` (pivoted, and the self-locking test). An
element whose friction moves no reaction (an input crank's pivot against the ground) is solved
by that sweep, from the others.

No solution: where that Newton does not converge in NEWTON_STEPS the equations have no
solution with the friction against the motion (**self-locking**): ``locked`` there.

One sample on Python numbers (an instant, the dynamics' right-hand side): :func:`solve_one`, one
Gauss–Seidel sweep and the same Newton in straight-line code generated per element count; None
where it gives up (the caller then takes :func:`solve`). The columns are rows of a workspace kept
per thread (:func:`_workspace`): fresh 64 kB temporaries cost more in page faults than in
arithmetic.
"""

from __future__ import annotations

import functools
import threading
from collections.abc import Sequence
from typing import Any

import numpy as np

__all__ = ["solve", "solve_one", "solve_flat", "newton", "NEWTON_STEPS", "FAST_STEPS", "ONE_SAMPLE_STEPS", "CONVERGED",
           "STAGNANT", "KEPT"]

#: Newton steps before a sample is declared self-locking (it converges quadratically: 3–6 steps).
NEWTON_STEPS = 60
#: Newton steps on whole columns (each after the second checked by a fixed-point sweep) before
#: the samples left go to the pivoted, per-sample Newton.
FAST_STEPS = 4
#: Converged when every |Δx| ≤ CONVERGED·max|x| (a few ulps).
CONVERGED = 16 * np.finfo(float).eps
#: A step this small relative to x that no longer halves is the rounding floor (converged); a
#: fixed-point residual beyond it means no solution.
STAGNANT = 1e-9


def _zero(a: np.ndarray) -> bool:
    """A response that is one broadcast zero (a load this output does not feel)."""
    return a.strides == (0,) and a.size > 0 and a[0] == 0


def solve(base: Sequence[np.ndarray], responses: Sequence[Sequence[np.ndarray]], dirs: Sequence[np.ndarray],
          carriers: Sequence[int], c: np.ndarray, n: int) -> tuple[np.ndarray, np.ndarray]:
    """x = c·|R₀ + B·x| per sample (module docstring): ``base`` the frictionless outputs,
    ``responses[j]`` the outputs under element j's unit load, ``dirs[j]`` its direction (n,),
    ``carriers[k]`` the output carrying element k's reaction; (x (n, m), self-locking mask (n,))."""
    m = len(carriers)
    if m == 0:
        return np.zeros((n, 0)), np.zeros(n, bool)
    cols = _Columns(base, responses, dirs, carriers, c, n)
    with np.errstate(invalid="ignore", over="ignore", divide="ignore"):
        if not cols.active:
            left = cols.sweep()  # (no element moves a reaction: x = c·|R₀|)
        for step in range(FAST_STEPS if cols.active else 0):
            cols.newton_step()
            if step > 0:  # checked (and the passive elements solved) by a fixed-point sweep
                left = cols.sweep()
                if not left.any():
                    break
    x = np.stack(cols.xs, axis=1)  # (a copy: the workspace is reused)
    if not left.any():
        return x, np.zeros(n, bool)
    idx = np.flatnonzero(left)
    x_left, locked_left = newton([r[idx] for r in cols.r0],
                                 [[np.broadcast_to(responses[j][k], (n,))[idx] for k in carriers] for j in range(m)],
                                 [np.broadcast_to(d, (n,))[idx] for d in dirs], c, idx.size, x[idx])
    x[idx] = x_left
    locked = np.zeros(n, bool)
    locked[idx] = locked_left
    return x, locked


class _Columns:
    """The magnitudes' equations on whole (n,) columns: the frictionless reactions R₀ (real and
    imaginary parts), per carrier the dⱼ·B_jk of the elements that move it, the magnitudes
    ``xs`` (x = 0 to start). Every column it writes is a row of one workspace kept per thread
    between calls (a block's temporaries, freshly allocated, cost more in page faults than in
    arithmetic: a new 64 kB column is 16 pages for the kernel to map and zero)."""

    def __init__(self, base: Sequence[np.ndarray], responses: Sequence[Sequence[np.ndarray]],
                 dirs: Sequence[np.ndarray], carriers: Sequence[int], c: np.ndarray, n: int) -> None:
        m = len(carriers)
        self.c, self.n, self.m = c, n, m
        self.r0 = [np.broadcast_to(base[k], (n,)) for k in carriers]
        self.r0re, self.r0im = [r.real for r in self.r0], [r.imag for r in self.r0]
        moved = [[k for k, out in enumerate(carriers) if not _zero(responses[j][out])] for j in range(m)]
        self.active = [j for j in range(m) if moved[j]]
        a = len(self.active)
        count = sum(len(v) for v in moved)
        rows = iter(_workspace(2 * count + 2 * m + a * a + 2 * a + 8, n))
        # per carrier k, the elements j whose friction moves it (a couple on an input crank
        # against the ground moves no reaction), with dⱼ·B_jk's real and imaginary parts
        self.terms: list[list[tuple[int, np.ndarray, np.ndarray]]] = [[] for _ in range(m)]
        for j in range(m):
            for k in moved[j]:
                resp = responses[j][carriers[k]]
                bre, bim = next(rows), next(rows)
                np.multiply(resp.real, dirs[j], out=bre)
                np.multiply(resp.imag, dirs[j], out=bim)
                self.terms[k].append((j, bre, bim))
        self.xs = [next(rows) for _ in range(m)]
        self.spare = [next(rows) for _ in range(m)]
        for x in self.xs:
            x.fill(0.0)
        self.zero = True  # x = 0 (the start): R = R₀
        self.matrix = [[next(rows) for _ in range(a)] for _ in range(a)]
        self.rhs = [next(rows) for _ in range(a)]
        self.solution = [next(rows) for _ in range(a)]
        self.re, self.im, self.tmp, self.change, self.size, self.s, self.cu_re, self.cu_im = (
            next(rows) for _ in range(8))

    def reaction(self, k: int) -> None:
        """re, im ← R_k at the current magnitudes."""
        re, im, tmp, xs = self.re, self.im, self.tmp, self.xs
        np.copyto(re, self.r0re[k])
        np.copyto(im, self.r0im[k])
        for j, bre, bim in () if self.zero else self.terms[k]:
            re += np.multiply(xs[j], bre, out=tmp)
            im += np.multiply(xs[j], bim, out=tmp)

    def modulus(self, out: np.ndarray) -> np.ndarray:
        """out ← |R| = √(re² + im²) (np.hypot's care for overflow costs 15 times more)."""
        np.multiply(self.re, self.re, out=out)
        out += np.multiply(self.im, self.im, out=self.tmp)
        return np.sqrt(out, out=out)

    def sweep(self) -> np.ndarray:
        """One Gauss–Seidel sweep x_k ← c_k·|R_k| over every element: the samples where an
        active element's x moved by more than CONVERGED·max|x| (a few ulps)."""
        c, tmp, change, size = self.c, self.tmp, self.change, self.size
        change.fill(0.0)
        size.fill(0.0)
        for k in range(self.m):
            self.reaction(k)
            new = self.modulus(self.spare[k])
            new *= c[k]
            if k in self.active:
                np.maximum(change, np.abs(np.subtract(new, self.xs[k], out=tmp), out=tmp), out=change)
            np.maximum(size, new, out=size)
            self.xs[k], self.spare[k] = new, self.xs[k]
        size *= CONVERGED
        return ~(change <= size)  # type: ignore[no-any-return]

    def newton_step(self) -> None:
        """One step of the directions' Newton (module docstring) on the active elements."""
        active, c, s, cu_re, cu_im, tmp = self.active, self.c, self.s, self.cu_re, self.cu_im, self.tmp
        where = {j: i for i, j in enumerate(active)}
        for i, k in enumerate(active):  # the system negated: (c·G − I)·x = −c·Re(ū·R₀)
            row = self.matrix[i]
            self.reaction(k)
            self.modulus(s)
            np.divide(c[k], s, out=s)
            np.multiply(self.re, s, out=cu_re)  # c·u
            np.multiply(self.im, s, out=cu_im)
            b = np.multiply(cu_re, self.r0re[k], out=self.rhs[i])
            b += np.multiply(cu_im, self.r0im[k], out=tmp)
            np.negative(b, out=b)
            filled = set()
            for j, bre, bim in self.terms[k]:  # c·dⱼ·Re(ū·B_jk)
                g = np.multiply(cu_re, bre, out=row[where[j]])
                g += np.multiply(cu_im, bim, out=tmp)
                filled.add(where[j])
            for q, g in enumerate(row):
                if q not in filled:
                    g.fill(0.0)
            row[i] -= 1.0
        _eliminate(self.matrix, self.rhs, self.solution, tmp)
        for i, j in enumerate(active):
            self.xs[j], self.solution[i] = self.solution[i], self.xs[j]
        self.zero = False


def _workspace(rows: int, n: int) -> list[np.ndarray]:
    """``rows`` scratch columns of n samples: rows of this thread's workspace (grown as needed),
    or of a fresh array where that would hold more than KEPT values (a synthesis population's
    block: not kept once solved)."""
    if rows * n > KEPT:
        return list(np.empty((rows, n)))
    work: np.ndarray | None = getattr(_LOCAL, "work", None)
    if work is None or work.shape[0] < rows or work.shape[1] < n:
        shape = (rows, n) if work is None else (max(rows, work.shape[0]), max(n, work.shape[1]))
        work = _LOCAL.work = np.empty(shape)
    return [work[i, :n] for i in range(rows)]


#: The most values (float64) a thread keeps as its workspace between calls: 16 MB, the columns
#: of a sweep block (solver.scene.CHUNK samples) for about eight elements all coupled.
KEPT = 1 << 21
_LOCAL = threading.local()


def _eliminate(rows: list[list[np.ndarray]], rhs: list[np.ndarray], x: list[np.ndarray], tmp: np.ndarray) -> None:
    """x ← the solution of the a × a system ``rows``·x = ``rhs`` per sample ((n,) columns), by
    Gaussian elimination without pivoting (diagonally dominant); ``rows`` and ``rhs`` overwritten."""
    a = len(rows)
    for p in range(a):
        pivot = rows[p][p]
        np.divide(1.0, pivot, out=pivot)  # (the pivot's column is not read again)
        for q in range(p + 1, a):
            rows[p][q] *= pivot
        rhs[p] *= pivot
        for i in range(p + 1, a):
            f = rows[i][p]
            for q in range(p + 1, a):
                rows[i][q] -= np.multiply(f, rows[p][q], out=tmp)
            rhs[i] -= np.multiply(f, rhs[p], out=tmp)
    for p in range(a - 1, -1, -1):
        np.copyto(x[p], rhs[p])
        for q in range(p + 1, a):
            x[p] -= np.multiply(rows[p][q], x[q], out=tmp)


def newton(r0c: list[np.ndarray], responses: list[list[np.ndarray]], dirs: list[np.ndarray],
           c: np.ndarray, n: int, start: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Newton on x = c·|R₀ + B·x| (an m × m system per sample, pivoted) from ``start``, with the
    self-locking test: (x, locked)."""
    m = len(r0c)
    r0 = np.stack(r0c, axis=1)  # (n, m)
    b = np.stack([np.stack(responses[j], axis=1) * dirs[j][:, None] for j in range(m)],
                 axis=1)  # (n, j, k): the response of carrier k to element j's friction
    x = start.copy()
    finite = np.isfinite(r0).all(axis=1) & np.isfinite(b).all(axis=(1, 2))
    x = np.where(np.isfinite(x), x, 0.0)
    done = ~finite
    eye = np.eye(m)
    last = np.full(n, np.inf)
    with np.errstate(invalid="ignore", divide="ignore", over="ignore"):
        for _ in range(NEWTON_STEPS):
            live = ~done
            if not live.any():
                break
            xl, bl = x[live], b[live]
            r = r0[live] + np.einsum("nj,njk->nk", xl, bl)
            a = np.abs(r)
            f = xl - c * a
            safe = np.where(a > 0.0, a, 1.0)[:, None, :]
            g = np.where(a[:, None, :] > 0.0, (np.conj(r)[:, None, :] * bl).real / safe, 0.0)  # ∂|R_k|/∂x_j
            jac = eye - np.swapaxes(g, 1, 2) * c[None, :, None]  # (n, k, j)
            try:
                dx = np.linalg.solve(jac, f[..., None])[..., 0]
            except np.linalg.LinAlgError:
                dx = np.full_like(xl, np.nan)
            xn = xl - dx
            ok = np.isfinite(xn).all(axis=1)
            step, size = np.abs(dx).max(axis=1), np.maximum(np.abs(xn).max(axis=1), 1e-300)
            # converged: a step of a few ulps, or steps at the rounding floor of an ill-conditioned
            # sample (near self-locking 1/(1 − gain) amplifies the rounding) that no longer shrink
            small = ok & ((step <= CONVERGED * size) | ((step <= STAGNANT * size) & (step >= 0.5 * last[live])))
            last[live] = step
            x[live] = np.where(ok[:, None], xn, x[live])
            idx = np.flatnonzero(live)
            done[idx[small]] = True
            bad = idx[~ok]
            done[bad] = True
            finite[bad] = False
    # the converged magnitudes are c·|R| (≥ 0) to round-off; anything else has no solution
    r = r0 + np.einsum("nj,njk->nk", x, b)
    residual = np.abs(x - c * np.abs(r)).max(axis=1)
    solved = done & finite & (residual <= STAGNANT * np.maximum(np.abs(x).max(axis=1), 1e-300))
    locked = ~solved & np.isfinite(r0).all(axis=1)
    return x, locked





def solve_one(r0: Sequence[complex], b: Sequence[Sequence[complex]], dirs: Sequence[float],
              c: Sequence[float], *,
              shift: tuple[Sequence[complex], float, Sequence[float]] | None = None) -> list[float] | None:
    """x = c·|R₀ + Σⱼ xⱼ·dⱼ·B_j| at one sample on Python numbers (the dynamics' right-hand side,
    one instant). ``shift`` = (A, s, v): the system with one more unknown eliminated (forward
    dynamics' ε, solver.dynamics._friction), R₀_k + A_k·s for R₀_k and B_jk − A_k·vⱼ for B_jk,
    formed inside. From x = c·|R₀| one Gauss–Seidel sweep, then the directions' Newton of
    :func:`solve` (the m × m system eliminated without pivoting: I − c·G is diagonally dominant
    while the gain is below 1), each step checked by the evaluation x ← c·|R(x)| to
    CONVERGED·max x — two steps at the usual gains; in straight-line code generated for this m
    (:func:`_unrolled`: a loop over the elements costs Python three times the arithmetic).
    None where ONE_SAMPLE_STEPS steps do not settle or a pivot vanishes (the caller hands the
    sample to :func:`solve`, whose pivoted per-sample Newton also tells self-locking)."""
    return _unrolled(len(r0))(r0, b, dirs, c, shift) if r0 else []  # type: ignore[no-any-return]


#: Newton steps of :func:`solve_one` before it gives up (two at the usual gains).
ONE_SAMPLE_STEPS = 6


def solve_flat(m: int, layout: tuple[int, int, Sequence[int], Sequence[int], Sequence[int]]) -> Any:
    """:func:`solve_one` with ``shift`` reading its inputs from one flat sequence (a compiled
    instant's output, solver.dynamics._friction): ``layout`` = (the index of R₀_0, of A_0, of each
    uⱼ, of each B_j0, of each element's v′ⱼ; R₀_k, A_k, B_jk at k past them). The function
    returned, ``f(flat, d, c, s, mass)``, gives (x, Σⱼ xⱼ·dⱼ·uⱼ, Σⱼ xⱼ·dⱼ·v′ⱼ) with x =
    ``solve_one(R₀, B, d, c, shift=(A, s, [uⱼ/mass]))`` — the same generated source after its first
    lines (tests/friction/test_friction_solve.py compares them to the bit) — without building those
    lists; None where that is None."""
    ir, ia, iu, ib, iv = layout
    return _unrolled(m, (ir, ia, tuple(iu), tuple(ib), tuple(iv)))


@functools.cache
def _unrolled(m: int, layout: tuple[int, int, tuple[int, ...], tuple[int, ...], tuple[int, ...]] | None = None
              ) -> Any:
    """:func:`solve_one` for m elements as one generated function on local variables (x_k, the
    reactions R_k, the system a_k_j·x_j = h_k of the Newton step); with ``layout``, the shifted
    system read from a flat sequence (:func:`solve_flat`)."""
    rng = range(m)

    def reaction(k: int) -> str:
        return f"r{k}" + "".join(f" + x{j} * b{j}_{k}" for j in rng)

    if layout is None:
        lines = [
            "def solve_one(r0, b, d, c, shift):",
            f"    {''.join(f'r{k}, ' for k in rng)}= r0",
            *(f"    {''.join(f'b{j}_{k}, ' for k in rng)}= b[{j}]" for j in rng),
            f"    {''.join(f'd{j}, ' for j in rng)}= d",
            f"    {''.join(f'c{k}, ' for k in rng)}= c",
            "    if shift is not None:",  # R₀ + A·s, B_jk − A_k·vⱼ
            f"        ({''.join(f'A{k}, ' for k in rng)}), s, ({''.join(f'v{j}, ' for j in rng)}) = shift",
            *(f"        r{k} += A{k} * s" for k in rng),
            *(f"        b{j}_{k} -= A{k} * v{j}" for j in rng for k in rng),
        ]
    else:  # the same shift, its inputs read from the flat sequence in place
        ir, ia, iu, ib, iv = layout
        lines = [
            "def solve_one(flat, d, c, s, mass):",
            *(f"    r{k} = flat[{ir + k}]" for k in rng),
            *(f"    b{j}_{k} = flat[{ib[j] + k}]" for j in rng for k in rng),
            f"    {''.join(f'd{j}, ' for j in rng)}= d",
            f"    {''.join(f'c{k}, ' for k in rng)}= c",
            *(f"    A{k} = flat[{ia + k}]" for k in rng),
            *(f"    v{j} = flat[{iu[j]}] / mass" for j in rng),
            *(f"    r{k} += A{k} * s" for k in rng),
            *(f"    b{j}_{k} -= A{k} * v{j}" for j in rng for k in rng),
        ]
    lines += [
        *(f"    b{j}_{k} *= d{j}" for j in rng for k in rng),  # dⱼ·B_jk
        *(f"    x{k} = c{k} * abs(r{k})" for k in rng),
        *(f"    x{k} = c{k} * abs({reaction(k)})" for k in rng),  # one Gauss–Seidel sweep
        *(f"    R{k} = {reaction(k)}" for k in rng),
        "    try:",
        f"        for _ in range({ONE_SAMPLE_STEPS}):",
    ]
    ind = " " * 12
    for k in rng:  # the row of element k: (1 − c_k·dⱼ·Re(ū_k·B_jk))·xⱼ … = c_k·Re(ū_k·R₀_k)
        lines.append(f"{ind}w = (R{k} * (c{k} / abs(R{k}))).conjugate()")
        lines.append(f"{ind}h{k} = (w * r{k}).real")
        lines += [f"{ind}a{k}_{j} = {'1.0 ' if j == k else ''}- (w * b{j}_{k}).real" for j in rng]
    for p in rng:  # Gaussian elimination, then back substitution
        lines.append(f"{ind}v = 1.0 / a{p}_{p}")
        lines += [f"{ind}a{p}_{q} *= v" for q in range(p + 1, m)]
        lines.append(f"{ind}h{p} *= v")
        for i in range(p + 1, m):
            lines.append(f"{ind}f = a{i}_{p}")
            lines += [f"{ind}a{i}_{q} -= f * a{p}_{q}" for q in range(p + 1, m)]
            lines.append(f"{ind}h{i} -= f * h{p}")
    for p in reversed(rng):
        lines.append(f"{ind}x{p} = h{p}" + "".join(f" - a{p}_{q} * x{q}" for q in range(p + 1, m)))
    lines += [f"{ind}R{k} = {reaction(k)}" for k in rng]
    lines += [f"{ind}n{k} = c{k} * abs(R{k})" for k in rng]
    news = ", ".join(f"n{k}" for k in rng)
    ret = f"[{news}]"
    if layout is not None:  # with the sums of x·d·u and x·d·v′ (as Python's sum of the products, to the bit)
        ret += "".join(", " + " + ".join(f"n{j} * d{j} * flat[{i[j]}]" for j in rng) for i in (iu, iv))
    lines += [f"{ind}t = {float(CONVERGED)!r} * max({news}, 0.0)",
              f"{ind}if {' and '.join(f'-t <= n{k} - x{k} <= t' for k in rng)}:",
              f"{ind}    return {ret}",
              "    except ZeroDivisionError:",
              "        return None",
              "    return None"]
    space: dict[str, Any] = {}
    exec(compile("\n".join(lines), f"<friction magnitudes, {m} elements>", "exec"), space)
    return space["solve_one"]
