#!/usr/bin/env python3
"""`mbrt hil --can udp://...` against python-can's udp_multicast bus (run
inside scripts/in-private-network: loopback only, TTL 0), in classic CAN
frames or, with `fd`, CAN FD frames (the model generated with --can-fd), on
python-can's default IPv4 or IPv6 group (`ipv6`: the namespace made with
in-private-network --ipv6). The
peer reads the model's DBC (tests/can/dbc.py), answers the states with
command frames, and sends one of each fault; the loop's report must count
exactly those.

  peer: the commands it accepted and refused, the states it sent (frames of
        the kind and length the DBC gives).
  log:  the bridge's candump log (--can-log), read with python-can's
        CanutilsLogReader and decoded with the DBC by the candied npm
        package, holds the commands the peer sent, value for value, and
        states whose seq and t agree. Skipped (77) without node or candied.

usage: python_can_peer.py MBRT MODEL WORK_DIR peer|log classic|fd ipv4|ipv6 [NODE_MODULES]
"""
import json
import os
import shutil
import socket
import subprocess
import sys
import time

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "hil"))
sys.path.insert(0, os.path.dirname(__file__))
import dbc  # noqa: E402
from hil_test import check, environment, finish  # noqa: E402

try:
    import can
    from can.interfaces.udp_multicast import UdpMulticastBus
except ImportError:
    print("SKIP: python3-can is not installed")
    sys.exit(77)

PORT = 43113  # python-can's default port; its default groups below
STATE_ID, COMMAND_ID = 0x100, 0x200
INT32_MIN = -(1 << 31)
MAX_AGE_S = 1.0  # generous: a busy machine must not make a command late
VALID = 40       # valid commands the peer sends
FD_LENGTHS = [*range(9), 12, 16, 20, 24, 32, 48, 64]

mbrt, model, work, mode, kind, family = sys.argv[1:7]
node_modules = sys.argv[7] if len(sys.argv) > 7 else ""
FD = kind == "fd"
if family == "ipv6":
    GROUP = UdpMulticastBus.DEFAULT_GROUP_IPv6
    BUS = f"udp://[{GROUP}]:{PORT}"
else:
    GROUP = UdpMulticastBus.DEFAULT_GROUP_IPv4
    BUS = f"udp://{GROUP}:{PORT}"
GEN = ["--can-fd"] if FD else []
if mode == "log" and (shutil.which("node") is None or not os.path.isdir(os.path.join(node_modules, "candied"))):
    print(f"SKIP: node or the candied package ({node_modules}) is missing; scripts/install-deps installs them")
    sys.exit(77)
env = environment(work)
name = os.path.splitext(os.path.basename(model))[0]
subprocess.run([mbrt, "gen", model, *GEN, "-o", os.path.join(work, "gen")], check=True)
messages = dbc.load(os.path.join(work, "gen", f"{name}.dbc"))
commands = sorted(i for i in messages if i >= COMMAND_ID)
inputs = [[s[0] for s in messages[i].signals[2:]] for i in commands]  # seq, state_seq, then the values
n_inputs = sum(len(names) for names in inputs)
factor = messages[commands[0]].signals[2][4]
# Build the loop's program before anything is timed.
subprocess.run([mbrt, "hil", model, *GEN, "--can", BUS, "--duration", "0"], env=env, stdout=subprocess.DEVNULL,
               check=True)

report, log = os.path.join(work, f"{mode}_hil.json"), os.path.join(work, f"{mode}.log")
hil = subprocess.Popen([mbrt, "hil", model, *GEN, "--can", BUS, "--rate", "1000", "--duration", "3",
                        "--max-command-age", str(MAX_AGE_S), "--command-timeout", str(MAX_AGE_S),
                        "--report", report, "--can-log", log], env=env, stdout=subprocess.DEVNULL)
bus = can.Bus(interface="udp_multicast", channel=GROUP, port=PORT, hop_limit=0)
state_seq = None
command_seqs = []  # command_seq of each state the peer received
odd_states = []    # state frames not of the kind and length the DBC gives


def take_states(seconds):
    global state_seq
    end = time.monotonic() + seconds
    while time.monotonic() < end:
        m = bus.recv(timeout=0.01)
        if m is None or not STATE_ID <= m.arbitration_id < COMMAND_ID:
            continue
        if m.is_fd != FD or len(m.data) != messages[m.arbitration_id].length:
            odd_states.append(m)
        elif m.arbitration_id == STATE_ID:
            s = messages[STATE_ID].decode(m.data)
            state_seq = s["seq"][0]
            command_seqs.append(s["command_seq"][0])


def send(seq, raw_values, wrong_length=None, is_fd=FD):
    """One command: its frames, raw values as the DBC encodes them. To make
    them malformed, wrong_length(n) gives the length of a frame the DBC gives
    n bytes (cut, or padded with zeros), or is_fd the other kind of frame."""
    raw_values = iter(raw_values)
    for frame_id, names in zip(commands, inputs):
        signals = {"seq": seq, "state_seq": state_seq, **{n: next(raw_values) for n in names}}
        data = messages[frame_id].encode(signals)
        if wrong_length:
            data = (data + bytes(64))[:wrong_length(len(data))]
        bus.send(can.Message(arbitration_id=frame_id, data=data, is_extended_id=False, is_fd=is_fd))


def raw(value):
    return round(value / factor)


sent = {}  # seq -> values of the valid commands
take_states(0.5)
check(state_seq is not None, "the peer received state frames")
for seq in range(VALID):
    values = [0.5 + 0.001 * seq - 0.25 * k for k in range(n_inputs)]
    send(seq, [raw(v) for v in values])
    sent[seq] = values
    take_states(0.01)
send(VALID, [INT32_MIN] * n_inputs)                # NaN: the invalid marker
send(VALID + 1, [raw(1000.0)] * n_inputs)          # beyond every input's limit
send(VALID + 2, [raw(0.125)] * n_inputs)           # valid...
sent[VALID + 2] = [0.125] * n_inputs
send(VALID + 2, [raw(0.125)] * n_inputs)           # ...and again: a duplicate
# Malformed commands, every frame counted: (wrong_length, is_fd, logged),
# logged telling whether the loop sees a frame (and logs it) at all.
malformed = [(lambda n: n - 1, False, True)]  # one byte short
if FD:
    malformed = [(lambda n: max(k for k in FD_LENGTHS if k < n), True, True),  # a shorter CAN FD length
                 (lambda n: 13, True, False),  # no CAN FD length: the datagram is refused whole
                 (lambda n: min(n, 8), False, True)]  # classic frames where CAN FD ones belong
for k, (wrong_length, is_fd, _) in enumerate(malformed):
    send(VALID + 3 + k, [raw(0.0)] * n_inputs, wrong_length, is_fd)
take_states(0.3)
bus.shutdown()  # python-can raises on the datagram that follows
with socket.socket(socket.AF_INET6 if family == "ipv6" else socket.AF_INET, socket.SOCK_DGRAM) as s:  # not msgpack at all
    if family == "ipv6":
        s.setsockopt(socket.IPPROTO_IPV6, socket.IPV6_MULTICAST_HOPS, 0)
    else:
        s.setsockopt(socket.IPPROTO_IP, socket.IP_MULTICAST_TTL, 0)
    s.sendto(b"\x93not a CAN message", (GROUP, PORT))
code = hil.wait(timeout=600)
check(code == 0, f"mbrt hil exit code {code}")
with open(report) as f:
    sim = json.load(f)

if mode == "peer":
    rejected = sim["commands_rejected"]
    check(sim["transport"] == "can " + BUS, f"transport {sim['transport']}")
    check(sim["cycles"] == 3000, f"the loop ran all its cycles ({sim['cycles']})")
    check(sim["commands_applied"] == VALID + 1, f"applied {sim['commands_applied']} == {VALID + 1}")
    expected = {"non_finite": 1, "out_of_range": 1, "duplicate": 1, "malformed": len(malformed) * len(commands) + 1,
                "late": 0, "out_of_order": 0}
    for reason, n in expected.items():
        check(rejected[reason] == n, f"{reason} rejections {rejected[reason]} == {n}")
    check(sim["commands_missing"] == 0, f"nothing missing ({sim['commands_missing']})")
    check(VALID + 2 in command_seqs, "the states reported the last applied command's sequence number")
    # Of the loop's 3000 states a loaded machine drops some in the peer's socket
    # buffer; a few hundred are plenty to show the frames' kind and lengths.
    check(len(command_seqs) > 300 and not odd_states,
          f"{len(command_seqs)} states, all in {kind} frames of the DBC's lengths (others: {odd_states[:3]})")
    check(sim["state_finite"] is True and sim["step_failures"] == 0, "the state stayed finite")
else:
    frames = [m for m in can.CanutilsLogReader(log)]
    check(len(frames) > 0, f"the log has {len(frames)} frames")
    lines = "".join(json.dumps({"id": m.arbitration_id, "data": list(m.data)}) + "\n" for m in frames)
    decoder = os.path.join(os.path.dirname(__file__), "decode_with_dbc.js")
    out = subprocess.run(["node", decoder, os.path.join(work, "gen", f"{name}.dbc")], input=lines, text=True,
                         capture_output=True, env=dict(os.environ, NODE_PATH=node_modules), check=True)
    decoded = [json.loads(line) for line in out.stdout.splitlines()]
    check(len(decoded) == len(frames), "candied answered every frame")
    names = [n for frame_names in inputs for n in frame_names]
    logged = {}  # (seq, input) -> value of the well-formed command frames
    states = []
    ill_formed = []
    disagreements = []  # frames candied reads otherwise than we do
    for m, d in zip(frames, decoded):
        if m.is_fd != FD or len(m.data) != messages[m.arbitration_id].length:
            ill_formed.append(m)
            # candied's own decode checks classic lengths; CAN FD ones only here (decode_with_dbc.js)
            if not FD and d is not None:
                disagreements.append(m)
            continue
        if d is None or d["format"] != ("StandardCAN_FD" if FD else None):
            disagreements.append(m)
            continue
        sig = d["signals"]
        if m.arbitration_id >= COMMAND_ID:
            for n in inputs[commands.index(m.arbitration_id)]:
                logged[(sig["seq"]["value"], names.index(n))] = sig[n]["value"]
        elif m.arbitration_id == STATE_ID:
            states.append((sig["seq"]["value"], sig["t"]["value"]))
    logged_faults = [fault for fault in malformed if fault[2]]
    check(len(ill_formed) == len(logged_faults) * len(commands) and all(m.arbitration_id >= COMMAND_ID for m in ill_formed),
          f"the only ill-formed frames in the log are the peer's malformed command frames ({len(ill_formed)})")
    check(not disagreements, f"candied decodes the well-formed frames as {kind} frames of the DBC, and only those "
                             f"({disagreements[:3]})")
    mismatched = [(seq, k) for seq, values in sent.items() for k, v in enumerate(values)
                  if abs(logged.get((seq, k), float("nan")) - v) > factor / 2]
    check(not mismatched, f"every command value sent is in the log ({len(sent)} commands; mismatched {mismatched[:5]})")
    seqs = [s for s, _ in states]
    check(len(states) == 3000 and seqs == list(range(3000)), f"the log holds every state, in order ({len(states)})")
    h = 1.0 / 1000  # one model step per cycle at 1 kHz for the models the tests use
    bad_t = [(s, t) for s, t in states if abs(t - (s + 1) * h) > 1e-5]
    check(not bad_t, f"each state's t is (seq + 1) h ({bad_t[:3]})")
finish()
