// Decodes CAN frames with a DBC file using the candied package, an
// independent DBC implementation. Reads JSON lines {"id": N, "data": [bytes]}
// on stdin and writes, per line, {"name": message, "signals": {name: {"value",
// "raw"}}} or null for a frame the DBC does not describe (unknown ID or
// length). usage: node decode_with_dbc.js FILE.dbc < frames.jsonl
const fs = require('fs');
const readline = require('readline');
const { Dbc, Can } = require('candied');

const can = new Can();
can.database = new Dbc().load(fs.readFileSync(process.argv[2], 'utf8'));

const lines = readline.createInterface({ input: process.stdin });
lines.on('line', (line) => {
  const frame = JSON.parse(line);
  const message = can.decode(can.createFrame(frame.id, frame.data));
  if (!message) {
    console.log('null');
    return;
  }
  const signals = {};
  message.boundSignals.forEach((s, name) => { signals[name] = { value: s.value, raw: s.rawValue }; });
  console.log(JSON.stringify({ name: message.name, signals }));
});
