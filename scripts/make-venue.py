#!/usr/bin/env python3
"""Generates the venue fixture (issue 16): an auditorium as an OBJ of about a
given triangle count, with its scene file and a rig of 48 moving heads on
three stage trusses plus 8 front-of-house profiles.

    scripts/make-venue.py --triangles 12000 -o fixtures            # the committed fixture
    scripts/make-venue.py --triangles 100000 -o /tmp/venue100k     # the bake-scaling sizes

writes OUT/venue.toml, OUT/venue/venue.obj and OUT/venue/venue.mtl. Python 3
standard library only; the same arguments give the same bytes.

The hall (metres, z up; the audience looks towards +y):
  * the room, 26 x 40 x 15 m, a box in the scene file (walls, ceiling, floor);
  * a stage deck 1.1 m high over y 28..40 with a proscenium wall at y = 28;
  * raked stalls (y 6..26): one step per row, its tread and riser as faces;
  * a balcony at the back (y 0..9, from 5 m up): slab, front, underside, its
    own rake;
  * seats as real geometry: cushion, a backrest of k facets (its curve), two
    armrests; k and the number of seats follow the triangle target;
  * four trusses (three over the stage, one front-of-house) of chords and
    cross members.
Faces are written as quads where they are planar (the loader keeps a planar
quad as one surface; bake_limits.h allows 65 536 surfaces), and counted as
two triangles each: "triangles" below is what a renderer would draw.
"""
import argparse
import math
import os

W, L, H = 26.0, 40.0, 15.0  # room
STAGE_Y, STAGE_Z = 28.0, 1.1
STALLS_Y0, STALLS_Y1 = 6.0, 26.0  # back and front of the stalls
BALC_Y1, BALC_Z = 9.0, 5.0
SEAT_W, ROW_D = 0.55, 0.9


class Obj:
    def __init__(self):
        self.v = []
        self.faces = []  # (material, [vertex indices, 1-based])
        self.material = None

    def quad(self, a, b, c, d):
        """Corners counter-clockwise seen from the lit side."""
        base = len(self.v)
        self.v.extend([a, b, c, d])
        self.faces.append((self.material, [base + 1, base + 2, base + 3, base + 4]))

    def box(self, lo, hi, omit=()):
        """Axis-aligned box, faces outward; omit: names of faces left out."""
        (x0, y0, z0), (x1, y1, z1) = lo, hi
        f = {
            "-x": [(x0, y0, z0), (x0, y0, z1), (x0, y1, z1), (x0, y1, z0)],
            "+x": [(x1, y0, z0), (x1, y1, z0), (x1, y1, z1), (x1, y0, z1)],
            "-y": [(x0, y0, z0), (x1, y0, z0), (x1, y0, z1), (x0, y0, z1)],
            "+y": [(x0, y1, z0), (x0, y1, z1), (x1, y1, z1), (x1, y1, z0)],
            "-z": [(x0, y0, z0), (x0, y1, z0), (x1, y1, z0), (x1, y0, z0)],
            "+z": [(x0, y0, z1), (x1, y0, z1), (x1, y1, z1), (x0, y1, z1)],
        }
        for name, corners in f.items():
            if name not in omit:
                self.quad(*corners)

    def triangles(self):
        return sum(len(f) - 2 for _, f in self.faces)


def seat(obj, x, y, z, k):
    """One seat facing +y, its front edge at y, floor at z, centred on x."""
    hw = SEAT_W / 2 - 0.03
    obj.material = "seat"
    obj.box((x - hw, y - 0.48, z + 0.38), (x + hw, y - 0.02, z + 0.48), omit=("-z",))
    # Backrest: k facets on an arc (its curve), each a slab 6 cm thick.
    r = 1.2
    half = math.asin(hw / r)
    yb, zb0, zb1 = y - 0.5, z + 0.48, z + 1.0
    for i in range(k):
        a0 = -half + 2 * half * i / k
        a1 = -half + 2 * half * (i + 1) / k
        p0 = (x + r * math.sin(a0), yb + r * (1 - math.cos(a0)))
        p1 = (x + r * math.sin(a1), yb + r * (1 - math.cos(a1)))
        b0 = (p0[0], p0[1] - 0.06)
        b1 = (p1[0], p1[1] - 0.06)
        obj.quad((p0[0], p0[1], zb0), (p1[0], p1[1], zb0), (p1[0], p1[1], zb1), (p0[0], p0[1], zb1))
        obj.quad((b1[0], b1[1], zb0), (b0[0], b0[1], zb0), (b0[0], b0[1], zb1), (b1[0], b1[1], zb1))
        obj.quad((p0[0], p0[1], zb1), (p1[0], p1[1], zb1), (b1[0], b1[1], zb1), (b0[0], b0[1], zb1))
    for side in (-1, 1):  # end caps of the backrest
        a = side * half
        p = (x + r * math.sin(a), yb + r * (1 - math.cos(a)))
        q = (p[0], p[1] - 0.06)
        if side < 0:
            obj.quad((p[0], p[1], zb0), (p[0], p[1], zb1), (q[0], q[1], zb1), (q[0], q[1], zb0))
        else:
            obj.quad((q[0], q[1], zb0), (q[0], q[1], zb1), (p[0], p[1], zb1), (p[0], p[1], zb0))
    obj.material = "armrest"
    for side in (-1, 1):
        ax = x + side * (SEAT_W / 2 - 0.015)
        obj.box((ax - 0.015, y - 0.5, z + 0.2), (ax + 0.015, y - 0.05, z + 0.68), omit=("-z",))


def rake(obj, x0, x1, y_front, rows, z0, rise, seats_per_row, k, material):
    """Rows stepping up away from the stage (towards -y); a seat row per step."""
    seats = 0
    for r in range(rows):
        y1 = y_front - r * ROW_D
        y0 = y1 - ROW_D
        z = z0 + r * rise
        obj.material = material
        obj.quad((x0, y0, z + rise), (x1, y0, z + rise), (x1, y1, z + rise), (x0, y1, z + rise))
        obj.quad((x0, y1, z), (x1, y1, z), (x1, y1, z + rise), (x0, y1, z + rise))  # riser
        width = x1 - x0
        n = min(seats_per_row, int(width / SEAT_W))
        start = (x0 + x1) / 2 - n * SEAT_W / 2 + SEAT_W / 2
        for s in range(n):
            seat(obj, start + s * SEAT_W, y1 - 0.05, z + rise, k)
            seats += 1
    return seats


def truss(obj, y, z, x0, x1, bays):
    """A box truss across x: four chords and a frame of cross members per bay."""
    obj.material = "truss"
    s = 0.3  # truss section, m
    t = 0.05  # chord and member size
    for dy in (0, s - t):
        for dz in (0, s - t):
            obj.box((x0, y + dy, z + dz), (x1, y + dy + t, z + dz + t))
    for b in range(bays + 1):
        x = x0 + (x1 - x0 - t) * b / bays
        obj.box((x, y + t, z), (x + t, y + s - t, z + t))
        obj.box((x, y + t, z + s - t), (x + t, y + s - t, z + s))
        obj.box((x, y, z + t), (x + t, y + t, z + s - t))
        obj.box((x, y + s - t, z + t), (x + t, y + s, z + s - t))


def build(per_row, k, stall_rows, balcony_rows, bays):
    obj = Obj()
    # Stage deck (front and top) and the proscenium wall with its opening.
    obj.material = "stage_floor"
    obj.quad((1, STAGE_Y, STAGE_Z), (W - 1, STAGE_Y, STAGE_Z), (W - 1, L, STAGE_Z), (1, L, STAGE_Z))
    obj.material = "masking"
    obj.quad((1, STAGE_Y, 0), (W - 1, STAGE_Y, 0), (W - 1, STAGE_Y, STAGE_Z), (1, STAGE_Y, STAGE_Z))
    obj.material = "wall"
    opening = (4.0, W - 4.0, 9.0)
    obj.quad((0, STAGE_Y - 0.4, 0), (opening[0], STAGE_Y - 0.4, 0), (opening[0], STAGE_Y - 0.4, H),
             (0, STAGE_Y - 0.4, H))
    obj.quad((opening[1], STAGE_Y - 0.4, 0), (W, STAGE_Y - 0.4, 0), (W, STAGE_Y - 0.4, H),
             (opening[1], STAGE_Y - 0.4, H))
    obj.quad((opening[0], STAGE_Y - 0.4, opening[2]), (opening[1], STAGE_Y - 0.4, opening[2]),
             (opening[1], STAGE_Y - 0.4, H), (opening[0], STAGE_Y - 0.4, H))
    # Stalls, then the balcony slab and its rake.
    seats = rake(obj, 1.5, W - 1.5, STALLS_Y1, stall_rows, 0.0, 0.12, per_row, k, "rake")
    obj.material = "balcony"
    obj.box((0.01, 0.01, BALC_Z - 0.5), (W - 0.01, BALC_Y1, BALC_Z), omit=("-y", "-x", "+x"))
    seats += rake(obj, 1.5, W - 1.5, BALC_Y1 - 0.3, balcony_rows, BALC_Z, 0.3, per_row, k, "rake")
    for y in (30.0, 33.0, 36.0):
        truss(obj, y, 9.5, 2.0, W - 2.0, bays)
    truss(obj, 22.0, 11.0, 3.0, W - 3.0, bays)
    return obj, seats


def choose(target):
    """Seats per row, rows, backrest facets and truss bays for about `target`
    triangles (an exhaustive search, deterministic): within 2 % of the
    target, the most seats (a bigger house before a finer seat), then the
    least detail; else the fewest triangles off."""
    best = None
    for per_row in (8, 12, 16, 24, 32, 41):
        for balcony_rows in (2, 3, 5, 7):
            for stall_rows in range(3, 23):
                for k in range(1, 40):
                    for bays in (2, 4, 8, 16, 32, 48):
                        # Triangles per seat: cushion 10, backrest 6k + 4, arms 20.
                        seats = (stall_rows + balcony_rows) * per_row
                        est = (seats * (34 + 6 * k) + 4 * (48 + 48 * (bays + 1)) + 40 +
                               4 * (stall_rows + balcony_rows))
                        off = abs(est - target)
                        key = (0 if off <= 0.02 * target else off, -seats, k, bays, off,
                               -per_row, balcony_rows)
                        if best is None or key < best[0]:
                            best = (key, per_row, k, stall_rows, balcony_rows, bays)
    return best[1:]


LUMINAIRES_HEADER = """# --- the rig: 48 moving heads on the three stage trusses (16 each,
# alternating profile spot and wash), 8 front-of-house profiles.
"""


def scene_text(obj_rel, triangles, faces, seats, patch_size, keep):
    out = [f"""# Generated by scripts/make-venue.py (issue 16): an auditorium of {triangles}
# triangles ({faces} faces, {seats} seats) and {keep} luminaires. Regenerate:
#   scripts/make-venue.py --triangles N -o DIR
# Metres, z up; the audience faces +y, the stage is y 28..40.

[scene]
name = "venue"
patch_size = {patch_size}

[camera]
position = [13.0, 3.0, 8.0]
target = [13.0, 34.0, 3.0]
fov = 70

[[material]]
name = "wall"
reflectance = [0.35, 0.3, 0.26]

[[material]]
name = "ceiling"
reflectance = 0.5

[[material]]
name = "floor"
reflectance = 0.12

[[box]]
name = "hall"
min = [0.0, 0.0, 0.0]
max = [{W}, {L}, {H}]
inward = true
material = "wall"
faces = {{ "+z" = "ceiling", "-z" = "floor" }}

[[mesh]]
file = "{obj_rel}"
"""]
    out.append(LUMINAIRES_HEADER)
    n = 0
    for t, y in enumerate((30.0, 33.0, 36.0)):
        for i in range(16):
            x = 2.6 + i * (W - 5.2) / 15
            spot = (i + t) % 2 == 0
            n += 1
            aim = (x + (3 if i < 8 else -3) * (t - 1) / 2, y - 2.0 + t, STAGE_Z)
            out.append("[[luminaire]]")
            out.append(f'name = "{"spot" if spot else "wash"}_{n:02d}"')
            out.append(f"position = [{x:.3f}, {y + 0.15:.2f}, 9.4]")
            out.append('mounting = "hanging"')
            out.append(f"aim_at = [{aim[0]:.3f}, {aim[1]:.2f}, {aim[2]:.2f}]")
            if spot:
                out.append("tilt_range = 268")
                out.append("sh_degree = 8")
                out.append('lid = { type = "beam", beam_angle = 24, field_angle = 34, '
                           'lumens = 12700, zoom = [12, 36] }')
            else:
                out.append("tilt_range = 232")
                out.append(f"colour = [{0.35 + 0.04 * t:.2f}, 0.55, 1.0]")
                out.append("sh_degree = 8")
                out.append('lid = { type = "beam", beam_angle = 34.5, lumens = 3850, '
                           'zoom = [11, 58] }')
            out.append("")
    for i in range(8):
        x = 3.5 + i * (W - 7.0) / 7
        out.append("[[luminaire]]")
        out.append(f'name = "foh_{i + 1}"')
        out.append(f"position = [{x:.3f}, 22.15, 10.9]")
        out.append('mounting = "hanging"')
        out.append(f"aim_at = [{W / 2 + (x - W / 2) * 0.6:.3f}, 31.0, 2.8]")
        out.append("colour = [1.0, 0.9, 0.78]")
        out.append("sh_degree = 6")
        out.append('lid = { type = "cos", exponent = 30, spread = 40, peak_cd = 60000 }')
        out.append("")
    text = "\n".join(out)
    if keep < 56:  # cut after the keep-th luminaire
        parts = text.split("[[luminaire]]")
        text = "[[luminaire]]".join(parts[:keep + 1]).rstrip() + "\n"
    return text


MTL = """# scripts/make-venue.py
newmtl seat
Kd 0.22 0.05 0.06
newmtl armrest
Kd 0.1 0.08 0.07
newmtl rake
Kd 0.12 0.1 0.09
newmtl stage_floor
Kd 0.2 0.2 0.2
newmtl masking
Kd 0.04 0.04 0.04
newmtl wall
Kd 0.35 0.3 0.26
newmtl balcony
Kd 0.5 0.45 0.38
newmtl truss
Kd 0.08 0.08 0.08
"""


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--triangles", type=int, default=12000, help="about how many (default 12000)")
    ap.add_argument("--patch-size", type=float, default=0.6, help="the scene's patch_size, m")
    ap.add_argument("--luminaires", type=int, default=56,
                    help="keep the first N of the 56 (scaling runs of the geometry alone)")
    ap.add_argument("-o", "--out", required=True, help="folder for venue.toml and venue/")
    args = ap.parse_args()
    if not 1 <= args.luminaires <= 56:
        ap.error("--luminaires: 1..56")
    if args.triangles < 2000:
        ap.error("--triangles: at least 2000 (the hall, trusses and a few seats)")
    per_row, k, stall_rows, balcony_rows, bays = choose(args.triangles)
    obj, seats = build(per_row, k, stall_rows, balcony_rows, bays)
    os.makedirs(os.path.join(args.out, "venue"), exist_ok=True)
    with open(os.path.join(args.out, "venue", "venue.mtl"), "w") as f:
        f.write(MTL)
    with open(os.path.join(args.out, "venue", "venue.obj"), "w") as f:
        f.write(f"# scripts/make-venue.py --triangles {args.triangles}: {obj.triangles()} "
                f"triangles, {len(obj.faces)} faces, {seats} seats, backrest facets {k}\n")
        f.write("mtllib venue.mtl\n")
        for p in obj.v:
            f.write("v %.4f %.4f %.4f\n" % p)
        current = None
        for material, face in obj.faces:
            if material != current:
                f.write(f"usemtl {material}\n")
                current = material
            f.write("f " + " ".join(str(i) for i in face) + "\n")
    with open(os.path.join(args.out, "venue.toml"), "w") as f:
        f.write(scene_text("venue/venue.obj", obj.triangles(), len(obj.faces), seats,
                           args.patch_size, args.luminaires))
    print(f"make-venue: {obj.triangles()} triangles, {len(obj.faces)} faces, {seats} seats "
          f"({per_row} a row, backrest facets {k}, {stall_rows} stall rows, {balcony_rows} balcony rows, "
          f"{bays} truss bays), {args.luminaires} luminaires -> {args.out}/venue.toml")


if __name__ == "__main__":
    main()
