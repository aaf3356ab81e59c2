#!/usr/bin/env python3
"""Print the mbrt model of a vehicle: a free chassis on independent suspensions.

Usage: tools/make_vehicle.py [--corners N] [--links 3|5] [--spin W] [--damping C] [--name NAME]
       > tests/models/stress/vehicle_4_suspensions.yaml

A 300 kg chassis (a 3.0 x 1.4 x 0.5 m box's inertia, centre of mass at
(0, 0, 0.5)), free in space: no joint to the ground and no ground contact,
so the vehicle falls under gravity -9.81 z. x points forward, y left, z up.
The N corners sit on ceil(N / 2) axles spread over a 2.4 m wheelbase
(front_left, front_right, rear_left, rear_right for N = 4), wheel centres
0.78 m either side of the centre line at z = 0.3.
Each corner is a closed loop that holds an upright (4 kg) to the chassis,
and a wheel (15 kg, radius 0.3 m) turns on the upright about a revolute
joint along y, spinning at --spin rad/s (default 10) at t = 0:

--links 5 (default), five-link: five rods (lower front, lower rear, upper
  front, upper rear, toe link), each a body with a spherical joint to the
  chassis and one to the upright. The five distances leave the upright one
  degree of freedom, its travel; each rod also turns freely about its own
  axis (a slender rod of radius 1 to 1.2 cm: small, nonzero axial inertia).
  7 bodies, 12 spherical joints and a revolute, 35 constraint rows.
--links 3, double wishbone: a lower and an upper arm (revolute joints to
  the chassis, axes along x) with spherical joints to the upright, and a tie
  rod (spherical at both ends) that holds the upright's steer.
  5 bodies, 2 revolute arms, 4 spherical joints and the hub, 27 rows.

No constraint is redundant, the joints hold exactly at t = 0 (every joint
point is a shared world point, each body placed from them) and every body
but the wheels starts at rest, so `mbrt sim` runs it without
--project-initial. Per corner a spring_damper (18 kN/m) acts between the
chassis and the lower arm (five-link: a point on the lower rear rod's axis),
compressed 2 cm at t = 0, so the suspensions oscillate while the vehicle
falls. Its damping is --damping N s/m, default 0: the model is then
conservative, so its energy must stay put.
"""
import argparse
import math
import sys

from make_spatial import add, fmt, quaternion_from_x, rod_inertia, scale, sub

GRAVITY = 9.81
WHEELBASE = 2.4
CHASSIS = {"mass": 300.0, "inertia": [55.0, 230.0, 270.0], "position": [0.0, 0.0, 0.5]}
WHEEL = {"mass": 15.0, "inertia": [0.35, 0.6, 0.35]}
UPRIGHT = {"mass": 4.0, "inertia": [0.03, 0.03, 0.008]}
STIFFNESS = 1.8e4
PRELOAD = 0.02

# Corner geometry for a left corner with its wheel centre at x = 0: (x, y, z) in
# world axes, y away from the centre line; right corners are the mirror image.
HUB = [0.0, 0.78, 0.30]
UPRIGHT_COM = [0.0, 0.69, 0.33]
SPRING_TOP = [0.0, 0.52, 0.70]
# Double wishbone: arms on revolute joints along x, spherical joints to the
# upright; their masses, centres of mass and principal inertias (world axes).
WISHBONE = {
    "lower": {"pivot": [0.0, 0.35, 0.20], "ball": [0.0, 0.68, 0.18], "mass": 3.0,
              "com": [0.0, 0.50, 0.19], "inertia": [0.028, 0.024, 0.05]},
    "upper": {"pivot": [0.0, 0.45, 0.50], "ball": [0.0, 0.66, 0.48], "mass": 2.0,
              "com": [0.0, 0.54, 0.49], "inertia": [0.012, 0.010, 0.021]},
}
TIE_ROD = {"inner": [-0.12, 0.36, 0.31], "outer": [-0.12, 0.69, 0.30], "mass": 0.6, "radius": 0.01}
SPRING_ON_LOWER_ARM = [0.0, 0.55, 0.19]
# Five-link: rods from a chassis point to an upright point.
RODS = [
    ("lower_front", [0.15, 0.35, 0.20], [0.04, 0.68, 0.18], 1.2, 0.012),
    ("lower_rear", [-0.15, 0.35, 0.20], [-0.04, 0.68, 0.17], 1.2, 0.012),
    ("upper_front", [0.12, 0.45, 0.50], [0.03, 0.66, 0.48], 0.8, 0.01),
    ("upper_rear", [-0.12, 0.45, 0.50], [-0.03, 0.66, 0.47], 0.8, 0.01),
    ("toe_link", [-0.15, 0.36, 0.31], [-0.13, 0.69, 0.30], 0.6, 0.01),
]
SPRING_ROD, SPRING_FRACTION = "lower_rear", 0.6   # the spring's point on that rod's axis, from inside


def corners(n):
    """(name, x of the wheel centre, side +1 left / -1 right) of n corners, front to rear."""
    axles = (n + 1) // 2
    if axles == 1:
        names = ["front"]
    elif axles == 2:
        names = ["front", "rear"]
    else:
        names = ["axle_%d" % k for k in range(axles)]
    out = []
    for i in range(n):
        k = i // 2
        x = 0.0 if axles == 1 else WHEELBASE / 2.0 - WHEELBASE * k / (axles - 1)
        out.append(("%s_%s" % (names[k], "left" if i % 2 == 0 else "right"), x, 1.0 if i % 2 == 0 else -1.0))
    return out


def body(name, mass, inertia, position, orientation=None, angular_velocity=None):
    return {"name": name, "mass": mass, "inertia": inertia, "position": position,
            "orientation": orientation or [1.0, 0.0, 0.0, 0.0],
            "angular_velocity": angular_velocity or [0.0, 0.0, 0.0]}


def rod(name, inner, outer, mass, radius):
    """A slender rod from inner to outer: centre between them, body x along the rod."""
    d = sub(outer, inner)
    length = math.sqrt(sum(x * x for x in d))
    return body(name, mass, rod_inertia(mass, length, radius), scale(0.5, add(inner, outer)),
                quaternion_from_x(scale(1.0 / length, d)))


def spherical(name, body1, body2, point):
    return {"name": name, "type": "spherical", "body1": body1, "body2": body2, "point": point}


def revolute(name, body1, body2, point, axis):
    return {"name": name, "type": "revolute", "body1": body1, "body2": body2, "point": point, "axis": axis}


def corner(prefix, x, side, links, spin, damping):
    """Bodies, joints and the spring of one corner."""
    def at(p):
        return [x + p[0], side * p[1], p[2]]

    upright, wheel = prefix + "_upright", prefix + "_wheel"
    bodies, joints = [], []
    if links == 3:
        for arm in ("lower", "upper"):
            a = WISHBONE[arm]
            name = "%s_%s_arm" % (prefix, arm)
            bodies.append(body(name, a["mass"], a["inertia"], at(a["com"])))
            joints.append(revolute("%s_%s_pivot" % (prefix, arm), "chassis", name, at(a["pivot"]), [1.0, 0.0, 0.0]))
            joints.append(spherical("%s_%s_ball" % (prefix, arm), name, upright, at(a["ball"])))
        tie = prefix + "_tie_rod"
        bodies.append(rod(tie, at(TIE_ROD["inner"]), at(TIE_ROD["outer"]), TIE_ROD["mass"], TIE_ROD["radius"]))
        joints.append(spherical(tie + "_inner", "chassis", tie, at(TIE_ROD["inner"])))
        joints.append(spherical(tie + "_outer", tie, upright, at(TIE_ROD["outer"])))
        spring_body, spring_point = prefix + "_lower_arm", at(SPRING_ON_LOWER_ARM)
    else:
        for rod_name, inner, outer, mass, radius in RODS:
            name = "%s_%s" % (prefix, rod_name)
            bodies.append(rod(name, at(inner), at(outer), mass, radius))
            joints.append(spherical(name + "_inner", "chassis", name, at(inner)))
            joints.append(spherical(name + "_outer", name, upright, at(outer)))
            if rod_name == SPRING_ROD:
                spring_body = name
                spring_point = add(at(inner), scale(SPRING_FRACTION, sub(at(outer), at(inner))))
    bodies.append(body(upright, UPRIGHT["mass"], UPRIGHT["inertia"], at(UPRIGHT_COM)))
    # The wheel's centre of mass is on the hub axis: spinning moves no centre.
    bodies.append(body(wheel, WHEEL["mass"], WHEEL["inertia"], at(HUB), angular_velocity=[0.0, spin, 0.0]))
    joints.append(revolute(prefix + "_hub", upright, wheel, at(HUB), [0.0, 1.0, 0.0]))
    top = at(SPRING_TOP)
    length = math.sqrt(sum(v * v for v in sub(spring_point, top)))
    spring = {"body1": "chassis", "body2": spring_body, "point1": top, "point2": spring_point,
              "stiffness": STIFFNESS, "damping": damping, "rest_length": length + PRELOAD}
    return bodies, joints, spring


def model(n, links, spin, damping, name, out):
    bodies = [body("chassis", CHASSIS["mass"], CHASSIS["inertia"], CHASSIS["position"])]
    joints, springs = [], []
    for prefix, x, side in corners(n):
        b, j, s = corner(prefix, x, side, links, spin, damping)
        bodies += b
        joints += j
        springs.append(s)
    rows = sum(3 if j["type"] == "spherical" else 5 for j in joints)
    kind = "five-link suspensions (5 rods" if links == 5 else "double-wishbone suspensions (2 arms, a tie rod"
    comment = ["Vehicle: a free 300 kg chassis (no ground, gravity -9.81 z) on %d independent" % n,
               "%s, upright, wheel spinning at %g rad/s), a spring_damper" % (kind, spin),
               "(%g N/m, %g N s/m, compressed %g m) from the chassis to each lower arm." % (STIFFNESS, damping, PRELOAD),
               "%d bodies, %d joints, %d constraint rows (%d per corner), no redundant row." % (
                   len(bodies), len(joints), rows, rows // n),
               "Generated by tools/make_vehicle.py --corners %d --links %d --spin %g --damping %g; do not edit by hand."
               % (n, links, spin, damping)]
    out.write("".join("# %s\n" % line for line in comment))
    out.write("name: %s\ngravity: [0, 0, %r]\nbodies:\n" % (name, -GRAVITY))
    for b in bodies:
        out.write("  - {name: %s, mass: %r, inertia: %s,\n     position: %s, orientation: %s,\n"
                  "     angular_velocity: %s}\n"
                  % (b["name"], b["mass"], fmt(b["inertia"]), fmt(b["position"]), fmt(b["orientation"]),
                     fmt(b["angular_velocity"])))
    out.write("joints:\n")
    for j in joints:
        extra = ", axis: %s" % fmt(j["axis"]) if j["type"] == "revolute" else ""
        out.write("  - {name: %s, type: %s, body1: %s, body2: %s, point: %s%s}\n"
                  % (j["name"], j["type"], j["body1"], j["body2"], fmt(j["point"]), extra))
    out.write("forces:\n")
    for s in springs:
        out.write("  - {type: spring_damper, body1: %s, body2: %s, point1: %s, point2: %s,\n"
                  "     stiffness: %r, damping: %r, rest_length: %s}\n"
                  % (s["body1"], s["body2"], fmt(s["point1"]), fmt(s["point2"]), s["stiffness"], s["damping"],
                     "%.17g" % s["rest_length"]))
    out.write("solver: {scheme: staggered-pcst, step: 0.001}\n")


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--corners", type=int, default=4, help="suspensions, two per axle (default 4)")
    parser.add_argument("--links", type=int, choices=[3, 5], default=5,
                        help="5: five-link suspensions (default), 3: double wishbones with a tie rod")
    parser.add_argument("--spin", type=float, default=10.0, help="wheel rate at t = 0, rad/s (default 10)")
    parser.add_argument("--damping", type=float, default=0.0, help="of the spring_dampers, N s/m (default 0)")
    parser.add_argument("--name", help="model name (default vehicle_N_suspensions, with _double_wishbone for --links 3)")
    args = parser.parse_args()
    if args.corners < 1:
        parser.error("--corners must be at least 1")
    if args.damping < 0:
        parser.error("--damping must not be negative")
    default = "vehicle_%d_suspensions%s" % (args.corners, "" if args.links == 5 else "_double_wishbone")
    model(args.corners, args.links, args.spin, args.damping, args.name or default, sys.stdout)


if __name__ == "__main__":
    main()
