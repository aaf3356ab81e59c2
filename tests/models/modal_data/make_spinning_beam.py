#!/usr/bin/env python3
"""Writes spinning_beam.yaml: a uniform cantilever of Euler-Bernoulli beam
elements (stiffness and geometric stiffness of Przemieniecki 1968, Theory of
Matrix Structural Analysis, ch. 5 and 15), its mass lumped at the nodes,
with the geometric stiffness of its spin and axial acceleration load cases
(docs/flexible.md, "Modal data from a file": geometric_stiffness).

usage: make_spinning_beam.py [ELEMENTS] > spinning_beam.yaml
   or: make_spinning_beam.py ELEMENTS --frequencies  (the spinning beam's
       lowest out-of-plane frequencies, all coordinates kept, for checking)
"""
import sys

import numpy as np

L, EA, GJ, EI, RHO_A = 1.0, 1.0e5, 1.0, 10.0, 1.0
C = 6  # coordinates a node: x y z rx ry rz


def element_stiffness(le):
    """12 x 12 in (node a, node b) x (x y z rx ry rz); rz = dv/dx, ry = -dw/dx."""
    k = np.zeros((12, 12))
    for i, j, s in ((0, 6, EA / le), (3, 9, GJ / le)):
        k[np.ix_([i, j], [i, j])] += s * np.array([[1, -1], [-1, 1]])
    bend = EI / le**3 * np.array([[12, 6 * le, -12, 6 * le], [6 * le, 4 * le**2, -6 * le, 2 * le**2],
                                  [-12, -6 * le, 12, -6 * le], [6 * le, 2 * le**2, -6 * le, 4 * le**2]])
    k[np.ix_([1, 5, 7, 11], [1, 5, 7, 11])] += bend          # v, rz = v'
    flip = np.diag([1, -1, 1, -1])                             # ry = -w'
    k[np.ix_([2, 4, 8, 10], [2, 4, 8, 10])] += flip @ bend @ flip
    return k


def element_geometric(le, tension):
    """The transverse geometric stiffness of an axial tension (N), both planes."""
    g = tension / (30 * le) * np.array([[36, 3 * le, -36, 3 * le], [3 * le, 4 * le**2, -3 * le, -le**2],
                                        [-36, -3 * le, 36, -3 * le], [3 * le, -le**2, -3 * le, 4 * le**2]])
    k = np.zeros((12, 12))
    k[np.ix_([1, 5, 7, 11], [1, 5, 7, 11])] += g
    flip = np.diag([1, -1, 1, -1])
    k[np.ix_([2, 4, 8, 10], [2, 4, 8, 10])] += flip @ g @ flip
    return k


def beam(elements):
    le = L / elements
    x = np.linspace(0, L, elements + 1)
    mass = np.full(elements + 1, RHO_A * le)
    mass[0] = mass[-1] = RHO_A * le / 2
    n = C * (elements + 1)
    K = np.zeros((n, n))
    spin, accel = np.zeros((n, n)), np.zeros((n, n))
    for e in range(elements):
        idx = list(range(C * e, C * e + 12))
        K[np.ix_(idx, idx)] += element_stiffness(le)
        # The axial force in element e: the nodes beyond it pull outwards
        # with m x per unit spin rate squared (about an axis through the root,
        # normal to the beam), and push towards the root with m per unit
        # acceleration of the structure along +x.
        beyond = slice(e + 1, elements + 1)
        spin[np.ix_(idx, idx)] += element_geometric(le, np.sum(mass[beyond] * x[beyond]))
        accel[np.ix_(idx, idx)] += element_geometric(le, -np.sum(mass[beyond]))
    return x, mass, K, spin, accel


def rows(matrix):
    fmt = lambda v: "0" if v == 0 else f"{v:.12g}"
    return "\n".join("  - [" + ", ".join(fmt(v) for v in row) + "]" for row in matrix)


def write(elements):
    x, mass, K, spin, accel = beam(elements)
    names = ["root"] + [f"n{k}" for k in range(1, elements)] + ["tip"]
    print(f"# A uniform 1 m cantilever of {elements} Euler-Bernoulli beam elements (EA {EA:g} N, GJ {GJ:g} N m^2,")
    print(f"# EI {EI:g} N m^2 in both planes, rho_A {RHO_A:g} kg/m), its mass lumped at the nodes (the")
    print("# clamped root's inertia gives the frame inertia about the beam), with the")
    print("# geometric stiffness of its spin about axes through the root (the file's")
    print("# origin) and of its acceleration along the beam. Written by")
    print("# make_spinning_beam.py (Przemieniecki 1968, Theory of Matrix Structural Analysis).")
    print("coordinates: 6\nnodes:")
    for name, xi, mi in zip(names, x, mass):
        # The clamped root's inertia gives the frame inertia about the beam.
        inertia = ", inertia: [0.001, 0.001, 0.001]" if name == "root" else ""
        print(f"  - {{name: {name}, position: [{xi:.12g}, 0, 0], mass: {mi:.12g}{inertia}}}")
    print("clamped: [root]\nstiffness:")
    print(rows(K))
    print("geometric_stiffness:")
    for case, m in (("spin_yy", spin), ("spin_zz", spin), ("acceleration_x", accel)):
        print(f"  {case}:")
        print("\n".join("  " + line for line in rows(m).split("\n")))


def frequencies(elements, spin_rate):
    """Out-of-plane (z) bending frequencies at a spin rate about z through the root."""
    _, mass, K, spin, _ = beam(elements)
    n = len(mass)
    Kt = K + spin_rate**2 * spin
    w = [C * k + 2 for k in range(1, n)]                      # w at the free nodes: with mass
    ry = [C * k + 4 for k in range(1, n)]                     # their slopes: condensed
    Kww, Kwr, Krr = Kt[np.ix_(w, w)], Kt[np.ix_(w, ry)], Kt[np.ix_(ry, ry)]
    Kc = Kww - Kwr @ np.linalg.solve(Krr, Kwr.T)
    M = np.diag(mass[1:])
    return np.sqrt(np.sort(np.linalg.eigvals(np.linalg.solve(M, Kc)).real))


if __name__ == "__main__":
    elements = int(sys.argv[1]) if len(sys.argv) > 1 else 12
    if "--frequencies" in sys.argv:
        scale = np.sqrt(EI / (RHO_A * L**4))
        for s in (0, 1, 2, 3, 4, 5):
            print(s, frequencies(elements, s * scale)[:2] / scale)
    else:
        write(elements)
