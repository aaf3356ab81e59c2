"""mbrt from Python: generate a model's step, build it and step it with numpy.

    import mbrt
    m = mbrt.load("four_bar.yaml", scheme="staggered-pcst", h=1e-3)
    m.step(1000)
    m.t, m.q, m.v, m.energy()

load() runs `mbrt gen`, compiles the generated model with a pybind11 binding
(binding.cpp.in) into a cache directory keyed by the hash of everything the
module is built from (like `mbrt sim`'s: $MBRT_CACHE_DIR, else
$XDG_CACHE_HOME/mbrt, else ~/.cache/mbrt) and imports it. docs/python.md.
"""

import collections
import hashlib
import importlib.util
import os
import pathlib
import shutil
import subprocess
import sysconfig
import tempfile

import numpy as np

__all__ = ["load", "Model", "Energy", "ModelError", "BuildError", "StepError"]

_HERE = pathlib.Path(__file__).resolve().parent
_TEMPLATE = _HERE / "binding.cpp.in"
_STATUS = {1: "non_finite", 2: "not_positive"}  # mbrt::StepStatus

Energy = collections.namedtuple("Energy", "kinetic potential total")


class ModelError(ValueError):
    """The model file is invalid; the message names the file, line and key."""


class BuildError(RuntimeError):
    """The generated model did not compile; the message names the compiler log."""


class StepError(RuntimeError):
    """A step failed (non-finite result or lost factorization); the state is the last good one."""


def _mbrt_executable(mbrt):
    candidates = [mbrt, os.environ.get("MBRT"), shutil.which("mbrt"), _HERE.parent.parent / "build" / "bin" / "mbrt"]
    for c in candidates:
        if c and pathlib.Path(c).is_file() and os.access(c, os.X_OK):
            return pathlib.Path(c).resolve()
    raise FileNotFoundError("mbrt executable not found: pass mbrt=PATH, set $MBRT, put mbrt on PATH "
                            "or build it in build/ (cmake --build build --target mbrt_cli)")


def _include_dirs(exe):
    """mbrt's runtime headers (installed beside the executable, else this source tree), Eigen, Python, pybind11."""
    installed = exe.parent.parent / "include"
    mbrt_include = installed if (installed / "mbrt" / "model_api.hpp").is_file() else _HERE.parent.parent / "include"
    if not (mbrt_include / "mbrt" / "model_api.hpp").is_file():
        raise FileNotFoundError(f"mbrt's runtime headers not found at {installed} or {mbrt_include}")
    dirs = [mbrt_include, pathlib.Path(sysconfig.get_paths()["include"])]
    for candidate in ("/usr/include/eigen3", "/usr/local/include/eigen3"):
        if (pathlib.Path(candidate) / "Eigen").is_dir():
            dirs.append(pathlib.Path(candidate))
            break
    else:
        raise FileNotFoundError("Eigen 3 headers not found (Debian: apt-get install libeigen3-dev)")
    return dirs


def _cache_root():
    for var, sub in (("MBRT_CACHE_DIR", ""), ("XDG_CACHE_HOME", "mbrt")):
        if os.environ.get(var):
            return pathlib.Path(os.environ[var]) / sub
    return pathlib.Path.home() / ".cache" / "mbrt"


def _compile_flags():
    flags = ["-std=c++20", "-O3", "-DNDEBUG", "-shared", "-fPIC", "-fvisibility=hidden"]
    try:  # as `mbrt sim`: AVX2 and FMA where the CPU has them
        cpu = pathlib.Path("/proc/cpuinfo").read_text()
        if " avx2" in cpu and " fma" in cpu:
            flags.append("-march=x86-64-v3")
    except OSError:
        pass
    return flags


def _generate(exe, model_file, options, out):
    if not pathlib.Path(model_file).is_file():
        raise FileNotFoundError(f"model file {model_file} does not exist")
    r = subprocess.run([str(exe), "gen", str(model_file), "-o", str(out), *options], capture_output=True, text=True)
    message = r.stderr.split("\n\nusage:")[0].strip().removeprefix("error: ")
    if r.returncode == 1:
        raise ModelError(message)
    if r.returncode != 0:
        raise ValueError(message)


def _build(exe, gen, name):
    """The extension module for the generated files in gen, from the cache or compiled into it."""
    includes = _include_dirs(exe)
    template = _TEMPLATE.read_text()
    key = hashlib.sha256()
    for f in sorted(gen.iterdir()):
        key.update(f.name.encode() + f.read_bytes())
    for f in sorted((includes[0] / "mbrt").rglob("*")):
        if f.is_file():
            key.update(f.name.encode() + f.read_bytes())
    compiler = os.environ.get("CXX", "c++")
    flags = _compile_flags()
    key.update((template + compiler + " ".join(flags) + " ".join(map(str, includes))).encode())
    module = f"mbrt_{name}_{key.hexdigest()[:16]}"
    target = _cache_root() / f"{name}-python-{key.hexdigest()[:16]}"
    library = target / (module + sysconfig.get_config_var("EXT_SUFFIX"))
    if not library.is_file():
        tmp = pathlib.Path(f"{target}.tmp{os.getpid()}")
        shutil.rmtree(tmp, ignore_errors=True)
        shutil.copytree(gen, tmp)
        binding = template.replace("@NAME@", name).replace("@UPPER@", name.upper()).replace("@MODULE@", module)
        (tmp / "binding.cpp").write_text(binding)
        command = [compiler, *flags, *(f"-I{d}" for d in includes), f"-I{tmp}", str(tmp / f"{name}.cpp"),
                   str(tmp / "binding.cpp"), "-o", str(tmp / library.name)]
        r = subprocess.run(command, capture_output=True, text=True)
        if r.returncode != 0:
            (tmp / "compile.log").write_text(" ".join(command) + "\n" + r.stderr)
            raise BuildError(f"compiling model '{name}' failed; see {tmp / 'compile.log'}")
        try:
            tmp.rename(target)  # atomic: concurrent loads never see a half-built module
        except OSError:
            shutil.rmtree(tmp, ignore_errors=True)  # another load built it first
    spec = importlib.util.spec_from_file_location(module, library)
    extension = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(extension)
    return extension


class Model:
    """A generated model's state, stepped in place.

    q: per body (body_names order) x, y, z and, for rigid bodies, Euler
    parameters e0..e3 (body to world); v: per body vx, vy, vz and, for rigid
    bodies, wx, wy, wz (body axes): the columns of `mbrt sim --out`
    (--velocities). Both are copies."""

    def __init__(self, extension):
        self._ext = extension
        self._sim = extension.Simulation()
        self.name, self.scheme, self.h = extension.name, extension.scheme, extension.h
        self.body_names = list(extension.body_names)
        self.body_rigid = list(extension.body_rigid)  # per body: rigid (7 values in q) or a particle (3)
        self.constraint_names = list(extension.constraint_names)
        self.input_names = list(getattr(extension, "input_names", []))
        self.output_names = list(getattr(extension, "output_names", []))

    def step(self, n=1):
        """Advances the state by n steps of h; raises StepError (the state is the last good one) if one fails."""
        if isinstance(n, bool) or not isinstance(n, (int, np.integer)) or n < 0:
            raise ValueError(f"step: n must be an integer >= 0, got {n!r}")
        status = self._sim.step(int(n))
        if status:
            raise StepError(f"model '{self.name}': step failed ({_STATUS.get(status, status)}) at t = {self.t}")

    def reset(self):
        """Back to the model file's initial state."""
        self._sim.reset()

    @property
    def t(self):
        return self._sim.t

    @property
    def q(self):
        return self._sim.q

    @property
    def v(self):
        return self._sim.v

    @property
    def state(self):
        """[q, v] as one array."""
        return np.concatenate([self.q, self.v])

    def energy(self):
        kinetic, potential = self._sim.energy()
        return Energy(kinetic, potential, kinetic + potential)

    def reactions(self):
        """Per joint and driver (constraint_names order): fx, fy, fz, tx, ty, tz on its body2, world axes."""
        return self._sim.reactions()

    def outputs(self):
        if not hasattr(self._sim, "outputs"):
            raise AttributeError(f"model '{self.name}' has no outputs")
        return self._sim.outputs()

    @property
    def inputs(self):
        if not hasattr(self._sim, "inputs"):
            raise AttributeError(f"model '{self.name}' has no inputs")
        return self._sim.inputs

    @inputs.setter
    def inputs(self, values):
        if not hasattr(self._sim, "inputs"):
            raise AttributeError(f"model '{self.name}' has no inputs")
        self._sim.inputs = np.asarray(values, dtype=float)


def load(model_file, scheme=None, h=None, name=None, mbrt=None, options=()):
    """Generates, builds (or takes from the cache) and loads a model.

    scheme, h and name override the model file's (`mbrt gen --scheme --h
    --name`); options passes further `mbrt gen` options. Raises ModelError on
    an invalid model file (the message names the file and line), ValueError
    on an invalid option, BuildError when the generated code does not compile."""
    args = []
    if scheme is not None:
        args += ["--scheme", str(scheme)]
    if h is not None:
        if isinstance(h, bool) or not isinstance(h, (int, float, np.floating, np.integer)):
            raise ValueError(f"h: expected a step in seconds, got {h!r}")
        args += ["--h", repr(float(h))]
    if name is not None:
        args += ["--name", str(name)]
    args += list(options)
    exe = _mbrt_executable(mbrt)
    with tempfile.TemporaryDirectory() as tmp:
        gen = pathlib.Path(tmp)
        _generate(exe, model_file, args, gen)
        model_name = next(gen.glob("*_c.h")).name.removesuffix("_c.h")
        return Model(_build(exe, gen, model_name))
