// Decodes CAN frames with a DBC file using the candied package, an
// independent DBC implementation. Reads JSON lines {"id": N, "data": [bytes]}
// on stdin and writes, per line, {"name": message, "format": its VFrameFormat
// ("StandardCAN_FD", or null where the DBC gives none), "signals": {name:
// {"value", "raw"}}} or null for a frame the DBC does not describe (unknown
// ID, or a classic frame of the wrong length).
// usage: node decode_with_dbc.js FILE.dbc < frames.jsonl
const fs = require('fs');
const readline = require('readline');
const { Dbc, Can } = require('candied');

const can = new Can();
can.database = new Dbc().load(fs.readFileSync(process.argv[2], 'utf8'));

// candied keeps an enumeration attribute's value as the index of its option.
function frameFormat(message) {
  const a = message.attributes.get('VFrameFormat');
  return a ? a.options[Number(a.value)] : null;
}

// candied 2.2 decodes classic frames only: Can.createFrame refuses payloads
// over 8 bytes, and its DBC grammar reads one digit of a BO_ length. A CAN FD
// frame is decoded signal by signal with its decodeSignal; the caller checks
// the frame's length against the DBC.
function decode(frame) {
  const message = can.getMessageById(frame.id);
  if (!message) return null;
  const format = frameFormat(message);
  let signals;
  if (format === 'StandardCAN_FD') {
    signals = new Map([...message.signals].map(([name, s]) => [name, can.decodeSignal(frame.data, s)]));
  } else {
    const bound = can.decode(can.createFrame(frame.id, frame.data));
    if (!bound) return null;
    signals = bound.boundSignals;
  }
  const out = {};
  signals.forEach((s, name) => { out[name] = { value: s.value, raw: s.rawValue }; });
  return { name: message.name, format, signals: out };
}

const lines = readline.createInterface({ input: process.stdin });
lines.on('line', (line) => console.log(JSON.stringify(decode(JSON.parse(line)))));
