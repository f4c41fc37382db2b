// The recording embedded in the page: parse it, inflate the packed columns, answer "where and
// what at time t" questions. Layout is written by sim/replay/encode.py.

async function inflate(b64) {
  if (!b64) return new Int32Array(0);
  const binary = atob(b64);
  const bytes = new Uint8Array(binary.length);
  for (let i = 0; i < binary.length; i++) bytes[i] = binary.charCodeAt(i);
  const stream = new Blob([bytes]).stream().pipeThrough(new DecompressionStream("deflate"));
  return new Int32Array(await new Response(stream).arrayBuffer());
}

// column-major differences → column-major values, in place
function undelta(values, rows, columns) {
  for (let c = 0; c < columns; c++) {
    let sum = 0;
    const base = c * rows;
    for (let r = 0; r < rows; r++) {
      sum += values[base + r];
      values[base + r] = sum;
    }
  }
  return values;
}

export function readData() {
  const element = document.getElementById("rdcd-replay-data");
  return JSON.parse(element.textContent);
}

export async function decode(data) {
  const n = data.poses.count;
  const m = data.modules.length;
  const channels = data.poses.channels;
  const times = undelta(await inflate(data.poses.times), n, 1);
  const poses = undelta(await inflate(data.poses.data), n, m * channels);
  const p = data.packets.count;
  const packets = undelta(await inflate(data.packets.data), p, 7);
  const column = (k) => packets.subarray(k * p, (k + 1) * p);
  const index = new Map(data.modules.map((module, i) => [module.id, i]));
  return {
    data, n, m, channels, index,
    times: Float64Array.from(times, (ms) => ms / 1000),
    poses,
    packets: {
      count: p, t: Float64Array.from(column(0), (ms) => ms / 1000), from: column(1), to: column(2),
      channel: column(3), size: column(4), kind: column(5), dropped: column(6),
    },
  };
}

// index of the last element of sorted `array` that is <= t, or -1
export function lastAtOrBefore(array, t) {
  let lo = 0;
  let hi = array.length - 1;
  let found = -1;
  while (lo <= hi) {
    const mid = (lo + hi) >> 1;
    if (array[mid] <= t) {
      found = mid;
      lo = mid + 1;
    } else {
      hi = mid - 1;
    }
  }
  return found;
}

export function roleAt(module, t) {
  let role = null;
  for (const [time, name] of module.role_history) {
    if (time <= t + 1e-9) role = name;
    else break;
  }
  return role;
}

// the pose channel that says whether a module is in the world (sim/replay/recording.py PRESENT)
export const PRESENT = 11;

// the latches closed at time t: [[a, a's connector, b, b's connector], ...] from data.links, each
// [t, a, ap, b, bp, 1 latched / 0 unlatched] in time order
export function linksAt(links, t) {
  const open = new Map();
  for (const [time, a, ap, b, bp, on] of links) {
    if (time > t + 1e-9) break;
    const key = `${a}.${ap}-${b}.${bp}`;
    if (on) open.set(key, [a, ap, b, bp]);
    else open.delete(key);
  }
  return [...open.values()];
}

// value of channel `c` of module `i` at sample `s`
export function channel(rec, i, c, s) {
  return rec.poses[(i * rec.channels + c) * rec.n + s];
}
