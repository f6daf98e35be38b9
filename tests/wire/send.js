// An independent DMX sender for relight's wire test (issue 12): the npm
// packages `sacn` (E1.31) and `artnet`, written by others, send one DMX
// frame to a unicast address, repeated like a console refreshing.
//
//   node send.js sacn|artnet UNIVERSE DEST_IP SLOT_CSV [REPEATS=10] [INTERVAL_MS=50]
//
// SLOT_CSV: values of slots 1, 2, ... (0..255); the rest of the universe is 0.
// Exit 0 when every packet went out, 1 on a send error, 2 on bad arguments.
'use strict';
const crypto = require('crypto');

const [protocol, universeText, dest, csv, repeatsText = '10', intervalText = '50'] = process.argv.slice(2);
const universe = Number(universeText);
const repeats = Number(repeatsText);
const intervalMs = Number(intervalText);
const slots = (csv || '').split(',').filter((s) => s !== '').map(Number);
if (!['sacn', 'artnet'].includes(protocol) || !(universe >= 0) || !dest || slots.length === 0 ||
    slots.some((v) => !Number.isInteger(v) || v < 0 || v > 255) || !(repeats >= 1)) {
  console.error('usage: node send.js sacn|artnet UNIVERSE DEST_IP SLOT_CSV [REPEATS] [INTERVAL_MS]');
  process.exit(2);
}
const sleep = (ms) => new Promise((resolve) => setTimeout(resolve, ms));

async function sendSacn() {
  const { Sender } = require('sacn');
  // A fresh CID every run: E1.31 receivers drop a known source whose sequence goes back.
  const sender = new Sender({
    universe,
    useUnicastDestination: dest,
    defaultPacketOptions: { cid: crypto.randomBytes(16), sourceName: 'relight wire test', useRawDmxValues: true },
  });
  const payload = {};
  slots.forEach((v, i) => { payload[i + 1] = v; });
  for (let k = 0; k < repeats; ++k) {
    await sender.send({ payload, priority: 100 });
    await sleep(intervalMs);
  }
  sender.close();
}

async function sendArtnet() {
  // A unicast host: the library does not bind port 6454 (it only does for a broadcast host), so the
  // receiver on this machine keeps the port to itself.
  const artnet = require('artnet')({ host: dest, sendAll: true, refresh: 60000 });
  // The library holds back a send within 25 ms of the last one and then never calls that send's
  // callback: keep the frames further apart.
  const gapMs = Math.max(intervalMs, 30);
  const full = new Array(512).fill(0);
  slots.forEach((v, i) => { full[i] = v; });
  for (let k = 0; k < repeats; ++k) {
    await new Promise((resolve, reject) => {
      artnet.data[universe] = undefined;  // resend even when unchanged
      artnet.set(universe, 1, full, (err) => (err ? reject(err) : resolve()));
    });
    await sleep(gapMs);
  }
  artnet.close();
}

(protocol === 'sacn' ? sendSacn() : sendArtnet()).then(
  () => process.exit(0),
  (err) => { console.error(`send.js: ${err}`); process.exit(1); });
