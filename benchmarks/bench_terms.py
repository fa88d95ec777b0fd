"""Cost of one row evaluation in the engine's dispatch: a contact row against a short-film row.

Each row is evaluated (force and Jacobian, :func:`rubrotor.core.terms.term_jac`) N times in a
compiled loop at a state where it acts (a contact 10 % of its clearance deep, a film at an
eccentricity ratio of 0.3 whirling), after a warm-up call; the median of 7 repetitions per row
is printed with the ratio. Run: ``python benchmarks/bench_terms.py``.
"""

import time

import numpy as np
from numba import njit

from rubrotor.core.contact import pack_contact
from rubrotor.core.terms import term_jac
from rubrotor.forces.film_row import FilmRow
from rubrotor.forces.fluid_film import ShortJournal

N = 200_000


@njit(cache=True)
def _loop(row, p, n):
    acc = 0.0
    for k in range(n):
        r = term_jac(p[0] + 1e-12 * k, p[1], p[2], p[3], row)
        acc += r[0] + r[5]
    return acc


def _median_ns(row, p) -> float:
    _loop(row, p, 10)
    times = []
    for _ in range(7):
        t = time.perf_counter()
        _loop(row, p, N)
        times.append(time.perf_counter() - t)
    return float(np.median(times)) / N * 1e9


def main():
    g = 1e-4
    contact = np.zeros(28)
    contact[:10] = pack_contact(1, 0, 1e10, 0.1, g, 0.1, 0, 20.0, 1e-3)
    jb = ShortJournal(diameter=0.05, length=0.02, radial_clearance=50e-6, viscosity=0.02)
    eq = jb.equilibrium((-150.0, 0.0), 600.0)
    co = jb.coefficients(eq.position, 600.0)
    film = FilmRow("b", 0.0, jb.film, True, tuple(eq.position), co.stiffness, co.damping)
    rows = {
        "contact (Hertz, friction)": (contact, np.array([1.1 * g, 0.0, 1e-3, 2e-3])),
        "short film (Ocvirk, pi-film)": (film.row(600.0), np.array([*eq.position, 1e-4, -1e-4])),
    }
    cost = {k: _median_ns(r, p) for k, (r, p) in rows.items()}
    for k, v in cost.items():
        print(f"{k:32s} {v:8.1f} ns per evaluation (force + Jacobian)")
    a, b = cost.values()
    print(f"film / contact: {b / a:.1f}x")


if __name__ == "__main__":
    main()
