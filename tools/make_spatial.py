#!/usr/bin/env python3
"""Print an mbrt model of a spatial stress case: a chain, an arm or a spinning body.

Usage:
  tools/make_spatial.py chain N [--joint spherical|revolute] [--mass KG] [--length M] [--name NAME]
  tools/make_spatial.py arm N [--name NAME]          (N = 6 or 7)
  tools/make_spatial.py spinner [--name NAME]
  tools/make_spatial.py humanoid [--name NAME]
  tools/make_spatial.py random N [--seed S] [--planar] [--name NAME]

Every model is conservative (gravity, no damping), so its energy must stay put.

chain: N slender rods (default 0.1 kg, 0.25 m, radius 4 % of the length:
  axial inertia about 200 times smaller than the transverse one) hanging from the origin, released from rest
  from a bent spatial shape (a quarter circle tilted 17 degrees down). On
  spherical joints, or on revolute joints whose axes alternate between the two
  directions normal to the rod. The free end whips.
arm: N links along +x, revolute axes alternating world z and y, masses from
  5 kg at the shoulder to 0.3 kg at the tool, started with joint rates that
  grow towards the tool (a light distal link that is whipped).
spinner: a light box (0.2 kg, principal inertias 1:2:3) on a spherical joint
  0.05 m from its centre, spinning at 300 rad/s about its intermediate axis
  with a small perturbation: it flips while it swings.
humanoid: a 30-dof branched tree shaped like a humanoid on a yaw pin at the
  pelvis: a 3-dof waist, a 2-dof neck, arms of 3 + 1 + 2 and legs of 3 + 1 + 2
  revolute joints (multi-axis joints as revolute joints in series through
  light links), every joint started at its own rate.
random: N revolute joints in a chain with random general axes, joint offsets,
  centres of mass off the link line, body orientations, masses (0.05 to 1 kg)
  and joint rates, drawn from --seed; --planar keeps every axis along world y
  and the links in the x-z plane. Models no one has tuned for: the class a
  generated step's cost and stability must hold on.

Initial velocities are consistent with the joints: they are computed here from
joint rates, so `mbrt sim` runs the models without --project-initial.
"""
import argparse
import random
import math
import sys

GRAVITY = 9.81


def add(a, b):
    return [x + y for x, y in zip(a, b)]


def sub(a, b):
    return [x - y for x, y in zip(a, b)]


def scale(s, a):
    return [s * x for x in a]


def cross(a, b):
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


def dot(a, b):
    return sum(x * y for x, y in zip(a, b))


def unit(a):
    return scale(1.0 / math.sqrt(dot(a, a)), a)


def quaternion_from_x(d):
    """Euler parameters of the shortest rotation taking the body x axis to the unit vector d."""
    x = [1.0, 0.0, 0.0]
    c = dot(x, d)
    if c < -1.0 + 1e-12:
        return [0.0, 0.0, 0.0, 1.0]
    axis = cross(x, d)
    e0 = math.sqrt((1.0 + c) / 2.0)
    return [e0] + scale(0.5 / e0, axis)


def rotate_transposed(q, v):
    """R(q)^T v: a world vector in body axes."""
    e0, e = q[0], q[1:]
    # R^T v = v + 2 e0 (v x e) + 2 e x (e x v)
    t = cross(e, v)
    return add(add(v, scale(-2.0 * e0, t)), scale(2.0, cross(e, t)))


def fmt(v):
    return "[" + ", ".join("%.17g" % x for x in v) + "]"


def rod_inertia(m, length, radius):
    axial = m * radius * radius / 2.0
    transverse = m * (3.0 * radius * radius + length * length) / 12.0
    return [axial, transverse, transverse]


def tree_velocities(bodies, joints):
    """COM velocities (world) and angular velocities (body axes) of a serial chain
    from the joints' relative angular velocities (world, at their points)."""
    omega = [0.0, 0.0, 0.0]
    anchors = []
    for body, joint in zip(bodies, joints):
        omega = add(omega, joint["rate"])
        anchors.append((joint["point"], joint["rate"]))
        v = [0.0, 0.0, 0.0]
        for point, rate in anchors:
            v = add(v, cross(rate, sub(body["position"], point)))
        body["velocity"] = v
        body["angular_velocity"] = rotate_transposed(body["orientation"], omega)


def write(name, comment, bodies, joints, step, out):
    out.write("".join("# %s\n" % line for line in comment))
    out.write("name: %s\ngravity: [0, 0, %r]\nbodies:\n" % (name, -GRAVITY))
    for b in bodies:
        out.write("  - {name: %s, mass: %r, inertia: %s,\n     position: %s, orientation: %s,\n"
                  "     velocity: %s, angular_velocity: %s}\n"
                  % (b["name"], b["mass"], fmt(b["inertia"]), fmt(b["position"]), fmt(b["orientation"]),
                     fmt(b["velocity"]), fmt(b["angular_velocity"])))
    out.write("joints:\n")
    for j in joints:
        extra = ", axis: %s" % fmt(j["axis"]) if j["type"] == "revolute" else ""
        out.write("  - {name: %s, type: %s, body1: %s, body2: %s, point: %s%s}\n"
                  % (j["name"], j["type"], j["body1"], j["body2"], fmt(j["point"]), extra))
    out.write("solver: {scheme: staggered-pcst, step: %r, euler_updates: 2}\n" % step)


def chain(n, joint_type, name, out, mass=0.1, length=0.25):
    radius = 0.04 * length
    tilt = 0.3
    bodies, joints, point = [], [], [0.0, 0.0, 0.0]
    for i in range(n):
        phi = 0.5 * math.pi * i / max(1, n - 1)
        d = [math.cos(phi) * math.cos(tilt), math.sin(phi) * math.cos(tilt), -math.sin(tilt)]
        q = quaternion_from_x(d)
        bodies.append({"name": "link_%d" % i, "mass": mass, "inertia": rod_inertia(mass, length, radius),
                       "position": add(point, scale(length / 2.0, d)), "orientation": q})
        joint = {"name": "joint_%d" % i, "type": joint_type, "body1": "ground" if i == 0 else "link_%d" % (i - 1),
                 "body2": "link_%d" % i, "point": point, "rate": [0.0, 0.0, 0.0]}
        if joint_type == "revolute":
            normal = unit(cross(d, [0.0, 0.0, 1.0]))
            joint["axis"] = normal if i % 2 == 0 else unit(cross(d, normal))
        joints.append(joint)
        point = add(point, scale(length, d))
    tree_velocities(bodies, joints)
    comment = ["Spatial %d-link chain on %s joints: rods of %g kg, %g m, radius %g m," % (n, joint_type, mass, length, radius),
               "hanging from the origin, released from rest bent (a quarter circle tilted down).",
               "Generated by tools/make_spatial.py chain %d --joint %s --mass %g --length %g; do not edit by hand."
               % (n, joint_type, mass, length)]
    write(name, comment, bodies, joints, 1.0e-3, out)


def arm(n, name, out):
    if n not in (6, 7):
        raise SystemExit("make_spatial.py arm: N must be 6 or 7")
    lengths = [0.4, 0.4, 0.3, 0.3, 0.15, 0.1, 0.08][-n:]
    masses = [5.0, 4.0, 3.0, 2.0, 1.0, 0.6, 0.3][-n:]
    radii = [0.05, 0.04, 0.035, 0.03, 0.025, 0.02, 0.02][-n:]
    rates = [1.0, -1.5, 2.0, -3.0, 4.0, -6.0, 8.0][-n:]
    bodies, joints, x = [], [], 0.0
    for i in range(n):
        bodies.append({"name": "link_%d" % i, "mass": masses[i],
                       "inertia": rod_inertia(masses[i], lengths[i], radii[i]),
                       "position": [x + lengths[i] / 2.0, 0.0, 0.0], "orientation": [1.0, 0.0, 0.0, 0.0]})
        axis = [0.0, 0.0, 1.0] if i % 2 == 0 else [0.0, 1.0, 0.0]
        joints.append({"name": "joint_%d" % i, "type": "revolute", "axis": axis,
                       "body1": "ground" if i == 0 else "link_%d" % (i - 1), "body2": "link_%d" % i,
                       "point": [x, 0.0, 0.0], "rate": scale(rates[i], axis)})
        x += lengths[i]
    tree_velocities(bodies, joints)
    comment = ["%d-link spatial arm: links along +x, revolute axes alternating z and y," % n,
               "5 kg shoulder link down to a 0.3 kg tool link, joint rates growing to the tool.",
               "Generated by tools/make_spatial.py arm %d; do not edit by hand." % n]
    write(name, comment, bodies, joints, 1.0e-3, out)


def spinner(name, out):
    mass = 0.2
    inertia = [1.0e-4, 2.0e-4, 3.0e-4]
    offset = 0.05
    body = {"name": "box", "mass": mass, "inertia": inertia, "position": [0.0, 0.0, -offset],
            "orientation": [1.0, 0.0, 0.0, 0.0]}
    w = [0.5, 300.0, 0.5]  # body = world axes at t = 0; the intermediate axis is y
    body["angular_velocity"] = w
    body["velocity"] = cross(w, [0.0, 0.0, -offset])
    joint = {"name": "pivot", "type": "spherical", "body1": "ground", "body2": "box", "point": [0.0, 0.0, 0.0]}
    comment = ["A light box (0.2 kg, principal inertias 1:2:3 x 1e-4) on a spherical joint 0.05 m",
               "above its centre, spinning at 300 rad/s about its intermediate axis (body y).",
               "Generated by tools/make_spatial.py spinner; do not edit by hand."]
    write(name, comment, [body], [joint], 1.0e-3, out)


def humanoid(name, out):
    bodies, joints = [], []
    index = {}

    def link(body, parent, axis, point, mass, com, inertia, rate):
        index[body] = len(bodies)
        bodies.append({"name": body, "mass": mass, "inertia": inertia, "position": com,
                       "orientation": [1.0, 0.0, 0.0, 0.0], "parent": parent})
        joints.append({"name": body + "_joint", "type": "revolute", "axis": axis,
                       "body1": parent, "body2": body, "point": point, "rate": scale(rate, axis)})

    x, y, z = [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]
    small = [1.0e-4, 1.0e-4, 1.0e-4]
    link("pelvis", "ground", z, [0.0, 0.0, 1.0], 8.0, [0.0, 0.0, 1.0], [0.08, 0.06, 0.1], 0.5)
    link("waist_1", "pelvis", x, [0.0, 0.0, 1.1], 0.2, [0.0, 0.0, 1.1], small, 0.8)
    link("waist_2", "waist_1", y, [0.0, 0.0, 1.1], 0.2, [0.0, 0.0, 1.1], small, -0.6)
    link("chest", "waist_2", z, [0.0, 0.0, 1.1], 12.0, [0.0, 0.0, 1.35], [0.3, 0.25, 0.12], 0.7)
    link("neck", "chest", y, [0.0, 0.0, 1.6], 0.3, [0.0, 0.0, 1.6], small, 1.2)
    link("head", "neck", z, [0.0, 0.0, 1.6], 4.0, [0.0, 0.0, 1.72], [0.02, 0.02, 0.015], -1.5)
    for side, s_ in (("left", 1.0), ("right", -1.0)):
        yy = 0.2 * s_
        link(side + "_shoulder_1", "chest", y, [0.0, yy, 1.5], 0.2, [0.0, yy, 1.5], small, 1.5 * s_)
        link(side + "_shoulder_2", side + "_shoulder_1", x, [0.0, yy, 1.5], 0.2, [0.0, yy, 1.5], small, -1.0)
        link(side + "_upper_arm", side + "_shoulder_2", z, [0.0, yy, 1.5], 2.0, [0.0, yy, 1.35],
             rod_inertia(2.0, 0.3, 0.04)[::-1], 2.0 * s_)
        link(side + "_forearm", side + "_upper_arm", y, [0.0, yy, 1.2], 1.2, [0.0, yy, 1.075],
             rod_inertia(1.2, 0.25, 0.03)[::-1], -2.5)
        link(side + "_wrist", side + "_forearm", x, [0.0, yy, 0.95], 0.2, [0.0, yy, 0.95], small, 3.0 * s_)
        link(side + "_hand", side + "_wrist", y, [0.0, yy, 0.95], 0.5, [0.0, yy, 0.9],
             [1.0e-3, 1.0e-3, 5.0e-4], 4.0)
        yl = 0.1 * s_
        link(side + "_hip_1", "pelvis", z, [0.0, yl, 0.95], 0.2, [0.0, yl, 0.95], small, -0.4 * s_)
        link(side + "_hip_2", side + "_hip_1", x, [0.0, yl, 0.95], 0.2, [0.0, yl, 0.95], small, 0.9)
        link(side + "_thigh", side + "_hip_2", y, [0.0, yl, 0.95], 6.0, [0.0, yl, 0.75],
             rod_inertia(6.0, 0.4, 0.06)[::-1], -1.2 * s_)
        link(side + "_shank", side + "_thigh", y, [0.0, yl, 0.55], 3.0, [0.0, yl, 0.35],
             rod_inertia(3.0, 0.4, 0.05)[::-1], 1.8)
        link(side + "_ankle", side + "_shank", y, [0.0, yl, 0.15], 0.2, [0.0, yl, 0.15], small, -2.0 * s_)
        link(side + "_foot", side + "_ankle", x, [0.0, yl, 0.15], 1.0, [0.05, yl, 0.1],
             [2.0e-3, 4.0e-3, 4.5e-3], 2.5)
    # Velocities from the joint rates along each body's path from ground.
    for b, j in zip(bodies, joints):
        path, parent = [j], b["parent"]
        while parent != "ground":
            k = index[parent]
            path.append(joints[k])
            parent = bodies[k]["parent"]
        omega = [0.0, 0.0, 0.0]
        v = [0.0, 0.0, 0.0]
        for joint in path:
            omega = add(omega, joint["rate"])
            v = add(v, cross(joint["rate"], sub(b["position"], joint["point"])))
        b["velocity"] = v
        b["angular_velocity"] = omega  # body axes = world axes at t = 0
    comment = ["30-dof humanoid-shaped tree on a yaw pin at the pelvis: waist 3, neck 2, arms 3 + 1 + 2,",
               "legs 3 + 1 + 2 revolute joints (light links between the axes of a multi-axis joint),",
               "every joint started at its own rate. Generated by tools/make_spatial.py humanoid; do not edit by hand."]
    write(name, comment, bodies, joints, 1.0e-3, out)


def random_chain(n, seed, planar, name, out):
    rng = random.Random(seed)

    def random_unit():
        while True:
            v = [rng.gauss(0, 1) for _ in range(3)]
            if math.sqrt(dot(v, v)) > 0.1:
                return unit(v)

    def random_rotation():
        if planar:  # about y
            half = rng.uniform(-1.5, 1.5)
            return [math.cos(half), 0.0, math.sin(half), 0.0]
        v = [rng.gauss(0, 1) for _ in range(4)]
        norm = math.sqrt(sum(x * x for x in v))
        return [x / norm * (1 if v[0] >= 0 else -1) for x in v]

    def in_plane(v):
        return [v[0], 0.0, v[2]] if planar else v

    bodies, joints, point = [], [], [0.0, 0.0, 0.0]
    for i in range(n):
        if planar:
            angle = rng.uniform(-2.5, -0.6)
            along = [math.cos(angle), 0.0, math.sin(angle)]
        else:
            along = random_unit()
            along[2] = -abs(along[2])
        length = rng.uniform(0.15, 0.35)
        com = add(point, add(scale(length * rng.uniform(0.3, 0.7), along), scale(0.02, in_plane(random_unit()))))
        mass = rng.uniform(0.05, 1.0)
        bodies.append({"name": "link_%d" % i, "mass": mass,
                       "inertia": [mass * 0.005 * rng.uniform(0.6, 1.0) for _ in range(3)],
                       "position": com, "orientation": random_rotation()})
        joints.append({"name": "joint_%d" % i, "type": "revolute",
                       "body1": "ground" if i == 0 else "link_%d" % (i - 1), "body2": "link_%d" % i,
                       "point": point, "axis": [0.0, 1.0, 0.0] if planar else random_unit()})
        point = add(point, add(scale(length, along), scale(0.03, in_plane(random_unit()))))
    for j in joints:
        j["rate"] = scale(rng.uniform(-1, 1), j["axis"])
    tree_velocities(bodies, joints)
    write(name, ["Random %s revolute chain, %d links, seed %d" % ("planar" if planar else "spatial", n, seed)],
          bodies, joints, 1e-3, out)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("kind", choices=["chain", "arm", "spinner", "humanoid", "random"])
    parser.add_argument("n", type=int, nargs="?", help="links (chain: N >= 1, arm: 6 or 7)")
    parser.add_argument("--joint", choices=["spherical", "revolute"], default="spherical", help="chain joints")
    parser.add_argument("--mass", type=float, default=0.1, help="chain: mass of a link, kg (default 0.1)")
    parser.add_argument("--length", type=float, default=0.25, help="chain: length of a link, m (default 0.25)")
    parser.add_argument("--seed", type=int, default=1, help="random: the draw (default 1)")
    parser.add_argument("--planar", action="store_true", help="random: a chain in the x-z plane")
    parser.add_argument("--name", help="model name")
    args = parser.parse_args()
    if args.kind in ("chain", "arm", "random") and (args.n is None or args.n < 1):
        parser.error("%s needs N >= 1" % args.kind)
    if args.kind == "chain":
        default = "chain_%d%s" % (args.n, "" if args.joint == "spherical" else "_revolute")
        if args.mass <= 0 or args.length <= 0:
            parser.error("--mass and --length must be positive")
        chain(args.n, args.joint, args.name or "spatial_" + default, sys.stdout, args.mass, args.length)
    elif args.kind == "arm":
        arm(args.n, args.name or "arm_%d" % args.n, sys.stdout)
    elif args.kind == "random":
        default = "%srandom_chain_%d_seed_%d" % ("planar_" if args.planar else "", args.n, args.seed)
        random_chain(args.n, args.seed, args.planar, args.name or default, sys.stdout)
    elif args.kind == "humanoid":
        humanoid(args.name or "humanoid_30", sys.stdout)
    else:
        spinner(args.name or "spinner", sys.stdout)


if __name__ == "__main__":
    main()
