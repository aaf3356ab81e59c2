"""What the HIL test scripts share: the loopback LCM URL, the programs'
cache, the controller's gains for the demo arm, and checks that report
each result and fail the script at the end."""
import os
import subprocess
import sys

LCM_URL = "udpm://239.255.76.67:7667?ttl=0"
GAINS = ["--kp", "200,60,10", "--kd", "20,6,1"]  # per joint of the demo arm
_failures = []


def environment(work):
    """The programs' environment: their compile cache is $MBRT_TEST_CACHE_DIR
    where the test sets one (ctest sets the tests' one cache, so each program
    is compiled once for all of them), else WORK/cache."""
    os.makedirs(work, exist_ok=True)
    return dict(os.environ, MBRT_CACHE_DIR=os.environ.get("MBRT_TEST_CACHE_DIR") or os.path.join(work, "cache"))


def compile_programs(mbrt, model, env, link=("--lcm", LCM_URL)):
    """Builds `mbrt hil` and `mbrt stub` for the model before anything is timed.
    The stub links the real-time library's objects the first build left in
    the cache (MBRT_CACHE_DIR/rt) and compiles none of its own."""
    rt = os.path.join(env["MBRT_CACHE_DIR"], "rt")

    def objects():
        return {f for f in os.listdir(rt) if f.endswith(".o")} if os.path.isdir(rt) else set()

    for command in ("hil", "stub"):
        before = objects()
        subprocess.run([mbrt, command, model, *link, "--duration", "0"], env=env,
                       stdout=subprocess.DEVNULL, check=True)
    check(before and objects() == before, "the stub reuses the compiled rt/ objects (%d in the cache)" % len(before))


def check(condition, what):
    print(("ok   " if condition else "FAIL ") + what)
    if not condition:
        _failures.append(what)


def finish():
    sys.exit(1 if _failures else 0)
