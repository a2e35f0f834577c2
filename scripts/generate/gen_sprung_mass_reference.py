#!/usr/bin/env python3
"""Independent reference for a sprung mass crossing a simply supported beam (REFERENCE.md §8).

The classic set-up: L = 25 m, E = 3.5e10 Pa, I = 1.3901 m^4, m = 18 358 kg/m, undamped; a mass
M = 5 750 kg on a spring k = 1.595e6 N/m whose lower end follows the beam (no unsprung mass),
v = 25 m/s, g = 9.81. Solved here without viaduct's code: the beam's exact modes
sin(i pi x / L) (modal mass m L / 2), the vehicle in absolute coordinates from its static
equilibrium on rigid ground, the first-order system integrated by SciPy's DOP853 at rtol 1e-11;
the same with twice the modes shows the modal truncation.

Also the two limits the brief names: a rigid spring (k -> infinity: the moving mass, with its
convective terms w_tt + 2 v w_xt + v^2 w_xx) and a soft one (k -> 0: the moving force M g).

Writes tests/data/vehicles/sprung_mass_25m.csv: t_s, mid_disp_m, body_disp_m, body_acc_mps2,
contact_N (the spring force plus M g on the beam), and moving_mass_mid_disp_m, every 5 ms over
the crossing (0..1 s). Run: /usr/bin/python3 scripts/generate/gen_sprung_mass_reference.py
"""
import os
import sys

import numpy as np
from scipy.integrate import solve_ivp

L, E, I, m = 25.0, 3.5e10, 1.3901, 18358.0
Mv, k, v, g = 5750.0, 1.595e6, 25.0, 9.81
EI = E * I
T = L / v


def omega(n):
    i = np.arange(1, n + 1)
    return (i * np.pi / L) ** 2 * np.sqrt(EI / m)


def sprung(n, rtol=1e-11):
    w = omega(n)
    mm = m * L / 2.0
    i = np.arange(1, n + 1)

    def rhs(t, y):
        q, qd, z, zd = y[:n], y[n:2 * n], y[2 * n], y[2 * n + 1]
        x = v * t
        phi = np.sin(i * np.pi * x / L)
        wx = phi @ q
        F = Mv * g + k * (z - wx)  # on the beam, down
        qdd = -w ** 2 * q + phi * F / mm
        zdd = -k * (z - wx) / Mv
        return np.concatenate([qd, qdd, [zd, zdd]])

    ts = np.linspace(0.0, T, 201)
    sol = solve_ivp(rhs, (0.0, T), np.zeros(2 * n + 2), method="DOP853", rtol=rtol, atol=1e-14, t_eval=ts)
    assert sol.success, sol.message
    q, z = sol.y[:n], sol.y[2 * n]
    mid = np.sin(i * np.pi / 2.0) @ q
    phi_t = np.sin(np.outer(i, np.pi * v * ts / L))
    wx = np.einsum("it,it->t", phi_t, q)
    contact = Mv * g + k * (z - wx)
    zdd = -k * (z - wx) / Mv
    return ts, mid, z, zdd, contact


def moving_mass(n, rtol=1e-11):
    """The rigid-spring limit: the mass rides on the beam, w_tt + 2 v w_xt + v^2 w_xx at x = v t."""
    w = omega(n)
    mm = m * L / 2.0
    i = np.arange(1, n + 1)
    a = i * np.pi / L

    def rhs(t, y):
        q, qd = y[:n], y[n:]
        x = v * t
        phi = np.sin(a * x)
        dphi = a * np.cos(a * x)
        ddphi = -a * a * phi
        # (mm I + Mv phi phi^T) qdd = -mm w^2 q + phi (Mv g - Mv (2 v dphi.qd + v^2 ddphi.q))
        A = mm * np.eye(n) + Mv * np.outer(phi, phi)
        b = -mm * w ** 2 * q + phi * (Mv * g - Mv * (2 * v * (dphi @ qd) + v * v * (ddphi @ q)))
        return np.concatenate([qd, np.linalg.solve(A, b)])

    ts = np.linspace(0.0, T, 201)
    sol = solve_ivp(rhs, (0.0, T), np.zeros(2 * n), method="DOP853", rtol=rtol, atol=1e-14, t_eval=ts)
    assert sol.success, sol.message
    return np.sin(i * np.pi / 2.0) @ sol.y[:n]


def main():
    root = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..")
    ts, mid, z, zdd, contact = sprung(20)
    _, mid2, z2, zdd2, c2 = sprung(40)
    print("modal truncation 20 -> 40 modes: mid %.2e, body %.2e, contact %.2e (relative to the peaks)"
          % (np.abs(mid - mid2).max() / np.abs(mid2).max(), np.abs(z - z2).max() / np.abs(z2).max(),
             np.abs(contact - c2).max() / (Mv * g)))
    mm20 = moving_mass(20)
    mm40 = moving_mass(40)
    print("moving mass 20 -> 40 modes: mid %.2e" % (np.abs(mm20 - mm40).max() / np.abs(mm40).max()))
    out = os.path.normpath(os.path.join(root, "tests", "data", "vehicles", "sprung_mass_25m.csv"))
    os.makedirs(os.path.dirname(out), exist_ok=True)
    with open(out, "w") as f:
        f.write("# Sprung mass on a 25 m simply supported beam (REFERENCE.md §8), 40 modes, DOP853 rtol 1e-11;\n")
        f.write("# made by scripts/generate/gen_sprung_mass_reference.py (independent of viaduct's code)\n")
        f.write("t_s,mid_disp_m,body_disp_m,body_acc_mps2,contact_N,moving_mass_mid_disp_m\n")
        for r in zip(ts, mid2, z2, zdd2, c2, mm40):
            f.write(",".join("%.12e" % x for x in r) + "\n")
    print("wrote", out)


if __name__ == "__main__":
    sys.exit(main())
