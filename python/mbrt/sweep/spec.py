"""The parameter sets of a sweep: a grid (`--grid`) or seeded random samples
(`--samples N --distribution SPEC --seed S`), each a dict KEY -> float in the
order the spec names the keys.

Grid: `KEY=A:B:N` (N values from A to B, both included) or `KEY=V1,V2,...`,
keys separated by commas: `link.mass=0.5:2.0:4,gravity.z=-9.81,-1.62`. The
grid is every combination, the last key varying fastest.

Distribution: `KEY=uniform(LOW,HIGH)`, `KEY=normal(MEAN,SD)`,
`KEY=lognormal(MU,SIGMA)` (MU and SIGMA of the underlying normal) or `KEY=V`
(fixed), separated by commas. Sample i draws from its own generator, seeded
with (S, i): its values depend on neither the executor nor the sample count.
"""
import itertools
import math
import re

import numpy as np

_KEY = r"[A-Za-z_][A-Za-z0-9_.]*"
_DISTRIBUTIONS = {  # name: (parameter names, draw, valid parameters)
    "uniform": ("LOW,HIGH", lambda rng, a, b: rng.uniform(a, b), lambda a, b: a <= b),
    "normal": ("MEAN,SD", lambda rng, a, b: rng.normal(a, b), lambda a, b: b >= 0),
    "lognormal": ("MU,SIGMA", lambda rng, a, b: rng.lognormal(a, b), lambda a, b: b >= 0),
}


class SpecError(ValueError):
    """A spec that does not parse; the message names the option and what was expected."""


def _number(text, option, where):
    try:
        value = float(text)
    except ValueError:
        value = math.nan
    if not math.isfinite(value):
        raise SpecError(f"{option}: '{where}': '{text}' is not a finite number")
    return value


def _assignments(spec, option, value_pattern):
    """[(KEY, VALUE TEXT)] of 'KEY=VALUE,KEY=VALUE', VALUE matching value_pattern (which may contain commas)."""
    pattern = re.compile(rf"\s*({_KEY})\s*=\s*({value_pattern})\s*(?:,|$)")
    out, pos = [], 0
    while pos < len(spec):
        m = pattern.match(spec, pos)
        if not m:
            raise SpecError(f"{option}: cannot read '{spec[pos:]}': expected KEY=VALUE (e.g. bob.mass=1.5)")
        if any(key == m.group(1) for key, _ in out):
            raise SpecError(f"{option}: key '{m.group(1)}' is given twice")
        out.append((m.group(1), m.group(2).strip()))
        pos = m.end()
    if not out:
        raise SpecError(f"{option}: empty; expected KEY=VALUE,...")
    return out


def grid(spec):
    """Every combination of the values the grid spec lists, as dicts."""
    axes = []
    # A value list runs up to the next 'KEY=' (values never contain '=').
    for key, text in _assignments(spec, "--grid", r"[^=]*?(?=,\s*" + _KEY + r"\s*=|$)"):
        where = f"{key}={text}"
        if ":" in text:
            parts = text.split(":")
            if len(parts) != 3:
                raise SpecError(f"--grid: '{where}': expected START:STOP:COUNT")
            start, stop = _number(parts[0], "--grid", where), _number(parts[1], "--grid", where)
            count = _number(parts[2], "--grid", where)
            if count < 1 or count != int(count):
                raise SpecError(f"--grid: '{where}': COUNT must be an integer >= 1, got '{parts[2]}'")
            values = [float(v) for v in np.linspace(start, stop, int(count))]
        else:
            values = [_number(v, "--grid", where) for v in text.split(",")]
        axes.append((key, values))
    keys = [key for key, _ in axes]
    return [dict(zip(keys, combination)) for combination in itertools.product(*(v for _, v in axes))]


def distribution(spec):
    """The distribution spec as [(KEY, draw(rng) -> float)], checked."""
    draws = []
    for key, text in _assignments(spec, "--distribution", r"[a-z]+\([^)]*\)|[^,]+"):
        where = f"{key}={text}"
        m = re.fullmatch(r"([a-z]+)\((.*)\)", text)
        if not m:
            value = _number(text, "--distribution", where)
            draws.append((key, lambda rng, v=value: v))
            continue
        name, args = m.group(1), [a.strip() for a in m.group(2).split(",")]
        if name not in _DISTRIBUTIONS:
            known = ", ".join(f"{n}({p})" for n, (p, _, _) in _DISTRIBUTIONS.items())
            raise SpecError(f"--distribution: '{where}': unknown distribution '{name}'; expected {known} or a number")
        names, draw, valid = _DISTRIBUTIONS[name]
        if len(args) != 2:
            raise SpecError(f"--distribution: '{where}': expected {name}({names})")
        a, b = (_number(x, "--distribution", where) for x in args)
        if not valid(a, b):
            raise SpecError(f"--distribution: '{where}': invalid parameters for {name}({names})")
        draws.append((key, lambda rng, draw=draw, a=a, b=b: float(draw(rng, a, b))))
    return draws


def format_value(value):
    """A parameter's value on a command line: at full precision, whole numbers without a point."""
    return str(int(value)) if value.is_integer() and abs(value) < 2**53 else repr(value)


def sample_seed(seed, index):
    """Sample index's own seed sequence under the sweep's seed."""
    return np.random.SeedSequence(seed, spawn_key=(index,))


def monte_carlo(spec, count, seed):
    """count samples of the distribution spec, sample i from its own generator (seed, i)."""
    draws = distribution(spec)
    samples = []
    for i in range(count):
        rng = np.random.default_rng(sample_seed(seed, i))
        samples.append({key: draw(rng) for key, draw in draws})
    return samples
