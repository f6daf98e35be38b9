#!/usr/bin/env python3
"""Writes fixtures/stage.dmxrec: the recorded console show of the stage fixture.

A 24 s chase on the 48 heads of fixtures/stage.dmx.toml, 44 DMX frames a
second on each of its two universes, as a console would send it: every head's
16-bit pan and tilt move in every frame (sine sweeps with a phase offset per
head, so the beams fan and cross), dimmer chases, colour changes (CMY and the
colour wheel on the spots, RGBW on the washes), zoom changes, a blackout
(the heads keep moving in the dark, as they do on a real rig) and a restore.

Format (one frame per line, read by hal's DMX replay):
    <time_us> <universe> <slot>=<hexbytes>[ <slot>=<hexbytes> ...]
slots 1-based; a hex run sets consecutive slots from there; slots not listed
keep the previous frame's value of that universe (all 0 before the first).
Only changed runs are written, so the file stays small.

Usage: scripts/make-stage-show.py [PATCH] [-o OUT]   (defaults: the stage's)
       scripts/make-stage-show.py --engine-replay OUT.replay [--seconds S]
The second form writes the same show's looks (pan/tilt in degrees, dimmer,
colour, zoom in degrees) as a relight replay script (fixtures/living_room.replay's format), so
relight-replay-hash and relight-render can play it without DMX: the stage's
48-head engine figures in docs/performance.md come from it.
Deterministic: no randomness, no clock; the same patch gives the same file.
Python 3.11 standard library only (tomllib).
"""
import argparse
import math
import os
import sys
import tomllib

FPS = 44
DURATION_S = 24.0

# Channel offsets from the start address, per (type file, mode), as the
# .qxf modes list them. tests/hal/dmx/stage_show_test.cc checks the show
# against hal's own personality of each type, so a wrong offset here fails.
SPOT = ("Martin/Martin-MAC-Quantum-Profile.qxf", "Basic")
WASH = ("Martin/Martin-MAC-Aura.qxf", "Standard Mode")
LAYOUT = {
    SPOT: dict(footprint=19, shutter=0, dimmer=1, cyan=2, magenta=3, yellow=4, wheel=5, zoom=12,
               pan=14, tilt=16, tilt_range=268, lens=(12, 36)),
    WASH: dict(footprint=14, shutter=0, dimmer=1, zoom=2, pan=3, tilt=5, wheel=8, red=9, green=10,
               blue=11, white=12, tilt_range=232, lens=(11, 58)),
}
PAN_RANGE_DEG = 540
SHUTTER_OPEN = 22          # open on both types (Quantum 20-49, Aura 20-24)
# Quantum Profile wheel slots (full slots, from the .qxf): open, blue, green,
# CTC 3200 K, magenta, congo blue, red.
WHEEL_SLOTS = [0, 15, 30, 45, 60, 75, 90]


def sixteen(deg, range_deg):
    """Degrees about the centre -> a 16-bit console value (32768 = 0)."""
    v = int(round(32768 + deg / range_deg * 65535))
    return max(0, min(65535, v))


def hsv_rgb(h):
    """Hue 0..1 at full saturation and value -> r, g, b in 0..1."""
    h = (h % 1.0) * 6
    i = int(h)
    f = h - i
    return [(1, f, 0), (1 - f, 1, 0), (0, 1, f), (0, 1 - f, 1), (f, 0, 1), (1, 0, 1 - f)][i % 6]


def byte(x):
    return max(0, min(255, int(round(x * 255))))


def look(t, truss, i, spot):
    """What head i (0..23) of a truss (0 downstage, 1 upstage) does at time t s."""
    ph = 2 * math.pi * i / 24
    # Position: downstage heads fan upstage (pan about 90 deg, beams towards
    # +y), upstage heads circle under their truss. Different rates per truss.
    if truss == 0:
        pan = 90 + 40 * math.sin(2 * math.pi * 0.21 * t + ph)
        tilt = 22 + 16 * math.sin(2 * math.pi * 0.33 * t + 2 * ph)
    else:
        pan = 90 + 70 * math.sin(2 * math.pi * 0.17 * t - ph)
        tilt = 10 + 22 * math.cos(2 * math.pi * 0.27 * t - ph)
    # Dimmer: a wave chase, then colour scenes, a blackout, a restore, a step chase.
    if t < 5:
        dim = 0.5 + 0.5 * math.sin(2 * math.pi * 0.6 * t - i * math.pi / 6)
    elif t < 13:
        dim = 1.0 if spot else 0.8
    elif t < 15:
        dim = 0.0                                    # blackout (the heads keep moving)
    elif t < 17:
        dim = 1.0                                    # restore: snap back to full
    else:
        step = int((t - 17) * 8)                     # 8 steps a second, 1 head in 4
        dim = 1.0 if (i + truss + step) % 4 == 0 else 0.15
    # Colour.
    hue = (t / 8 + i / 24 + truss * 0.5) % 1.0
    if t < 5:
        rgb = (1, 1, 1) if spot else ((0.2, 0.4, 1) if truss == 0 else (1, 0.5, 0.15))
        wheel = 0
    elif t < 9:
        rgb = hsv_rgb(hue)                           # CMY / RGB rainbow rolling along the truss
        wheel = 0
    elif t < 13:
        rgb = (1, 1, 1)
        wheel = WHEEL_SLOTS[1 + (int((t - 9) * 2) + i) % 6]  # wheel steps on the spots
        if not spot:
            rgb = hsv_rgb(0.6 + 0.1 * math.sin(t))
    else:
        rgb = hsv_rgb(hue) if t >= 17 else (1, 1, 1)
        wheel = 0
    # Zoom: breathing sweep 5-13 s, steps after the restore, mid before.
    if t < 5:
        zoom = 0.5
    elif t < 13:
        zoom = 0.5 + 0.5 * math.sin(2 * math.pi * 0.25 * (t - 5) + ph)
    else:
        zoom = [0.0, 1.0, 0.5, 0.2][int(t) % 4]
    return pan, tilt, dim, rgb, wheel, zoom


def frame(t, universe_fixtures):
    """The 512 slots of one universe at time t."""
    slots = [0] * 512
    for truss, i, address, kind in universe_fixtures:
        lay = LAYOUT[kind]
        spot = kind == SPOT
        pan, tilt, dim, rgb, wheel, zoom = look(t, truss, i, spot)
        base = address - 1

        def put(name, value):
            slots[base + lay[name]] = value

        put("shutter", SHUTTER_OPEN)
        put("dimmer", byte(dim))
        put("zoom", byte(zoom))
        p, tl = sixteen(pan, PAN_RANGE_DEG), sixteen(tilt, lay["tilt_range"])
        put("pan", p >> 8)
        slots[base + lay["pan"] + 1] = p & 255
        put("tilt", tl >> 8)
        slots[base + lay["tilt"] + 1] = tl & 255
        if spot:
            put("cyan", byte(1 - rgb[0]))          # subtractive: C = 1 - R
            put("magenta", byte(1 - rgb[1]))
            put("yellow", byte(1 - rgb[2]))
            put("wheel", wheel)
        else:
            w = min(rgb)                             # white carries the common part
            put("red", byte(rgb[0] - w))
            put("green", byte(rgb[1] - w))
            put("blue", byte(rgb[2] - w))
            put("white", byte(w))
    return slots


def pan_of(slots, address, kind):
    o = address - 1 + LAYOUT[kind]["pan"]
    return slots[o] << 8 | slots[o + 1]


def changed_runs(prev, cur, max_gap=2):
    """Runs of changed slots as (first slot 1-based, bytes); gaps of up to
    max_gap unchanged slots are written through (cheaper than a new run)."""
    runs = []
    start = end = None
    for s in range(512):
        if cur[s] != prev[s]:
            if start is not None and s - end - 1 <= max_gap:
                end = s
            else:
                if start is not None:
                    runs.append((start, end))
                start = end = s
    if start is not None:
        runs.append((start, end))
    return [(a + 1, bytes(cur[a:b + 1])) for a, b in runs]


def engine_replay(path, names, seconds):
    """The show's looks as a replay script: every head at every DMX frame,
    8 heads a line (the replay reader takes lines of up to 4096 bytes)."""
    lines = ["# the stage show's looks at 44 frames/s (scripts/make-stage-show.py --engine-replay)"]
    for k in range(int(seconds * FPS)):
        t = k / FPS
        sets = []
        for name, truss, i, kind in names:
            pan, tilt, dim, rgb, wheel, zoom = look(t, truss, i, kind == SPOT)
            lo, hi = LAYOUT[kind]["lens"]
            zoom_deg = hi - (hi - lo) * byte(zoom) / 255  # both zooms run big -> small
            sets.append(f"{name}.pan={pan:.3f} {name}.tilt={tilt:.3f} {name}.dimmer={dim:.4f} "
                        f"{name}.colour={rgb[0]:.4f},{rgb[1]:.4f},{rgb[2]:.4f} {name}.zoom={zoom_deg:.2f}")
        for j in range(0, len(sets), 8):
            lines.append(f"{t:.6f} " + " ".join(sets[j:j + 8]))
    with open(path, "w", encoding="ascii", newline="\n") as f:
        f.write("\n".join(lines) + "\n")
    print(f"{path}: {int(seconds * FPS)} frames, {len(names)} heads")


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    root = os.path.dirname(here)
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("patch", nargs="?", default=os.path.join(root, "fixtures", "stage.dmx.toml"))
    ap.add_argument("-o", "--output", default=os.path.join(root, "fixtures", "stage.dmxrec"))
    ap.add_argument("--engine-replay", metavar="OUT", help="write the looks as a relight replay script instead")
    ap.add_argument("--seconds", type=float, default=DURATION_S, help="with --engine-replay: how much of the show")
    args = ap.parse_args()

    with open(args.patch, "rb") as f:
        patch = tomllib.load(f)
    universes = {}
    names = []
    for fx in patch.get("dmx_fixture", []):
        kind = (fx["type"], fx["mode"])
        if kind not in LAYOUT:
            sys.exit(f"make-stage-show: {fx['name']}: no channel layout for {kind}")
        truss = 0 if fx["name"].startswith("ds_") else 1
        i = int(fx["name"].rsplit("_", 1)[1]) - 1
        universes.setdefault(fx["universe"], []).append((truss, i, fx["address"], kind))
        names.append((fx["name"], truss, i, kind))
    if args.engine_replay:
        engine_replay(args.engine_replay, names, args.seconds)
        return

    frames = int(DURATION_S * FPS)
    prev = {u: [0] * 512 for u in universes}
    lines = [
        "# relight DMX recording: the stage show (fixtures/stage.toml, patch fixtures/stage.dmx.toml)",
        f"# written by scripts/make-stage-show.py; {FPS} frames/s per universe, {frames} frames, "
        f"universes {' '.join(str(u) for u in sorted(universes))}",
        "# <time_us> <universe> <slot>=<hexbytes> ...: slots 1-based, unlisted slots keep their value",
    ]
    for k in range(frames):
        t_us = k * 1000000 // FPS
        t = k / FPS
        for u in sorted(universes):
            cur = frame(t, universes[u])
            # Every head's pan moves in every frame: a sweep at its turning
            # point can repeat a 16-bit value, so nudge it by one LSB.
            for truss, i, address, kind in universes[u]:
                if k > 0 and pan_of(cur, address, kind) == pan_of(prev[u], address, kind):
                    o = address - 1 + LAYOUT[kind]["pan"]
                    v = pan_of(cur, address, kind)
                    v = v + 1 if v < 65535 else v - 1
                    cur[o], cur[o + 1] = v >> 8, v & 255
            runs = changed_runs(prev[u], cur)
            lines.append(f"{t_us} {u} " + " ".join(f"{s}={b.hex()}" for s, b in runs))
            prev[u] = cur
    tmp = args.output + ".tmp"
    with open(tmp, "w", encoding="ascii", newline="\n") as f:
        f.write("\n".join(lines) + "\n")
    os.replace(tmp, args.output)
    print(f"{args.output}: {frames} frames x {len(universes)} universes, {os.path.getsize(args.output)} bytes")


if __name__ == "__main__":
    main()
