#!/usr/bin/env python3
"""Generate the example Kerf documents in resources/examples/.

Usage:  python3 tools/make_examples.py [OUTPUT_DIR]

Writes five furniture-part documents (format: shared/spec/document-format.md,
version 1; Z up, millimetres, degrees):

  side-chair.kerf      side chair, the default example
  bookshelf-side.kerf  bookshelf side panel with shelf-pin holes and a back groove
  table-top.kerf       rounded table top with leg mortises on the underside
  stool.kerf           round stool with splayed legs and a foot ring
  door-frame.kerf      frame-and-panel cabinet door with hinge cup holes

The script only writes JSON; validate each result with `kerf check FILE`.
Everything here is plain arithmetic: the only non-trivial geometry is the arc
profile of the chair's curved back rails and the placement of tilted parts.
"""

import json
import math
import os
import sys

# Wood tones used for colours.
OAK = "#c49a6c"
WALNUT = "#6b4a2f"
CHERRY = "#9c5b3b"
MAPLE = "#e0c49a"
BEECH = "#d2a679"
ASH = "#cfb48a"


def num(v):
    """Round to 1/1000 mm and write whole numbers without a fraction."""
    v = round(float(v), 3)
    if v == 0:
        return 0
    return int(v) if v == int(v) else v


def vec(*vs):
    return [num(v) for v in vs]


def xf(translate=None, rotate=None):
    t = {}
    if translate is not None and any(abs(c) > 1e-9 for c in translate):
        t["translate"] = vec(*translate)
    if rotate is not None and any(abs(c) > 1e-9 for c in rotate):
        t["rotate"] = vec(*rotate)
    return t


def node(id_, type_, name=None, translate=None, rotate=None, color=None, **params):
    n = {"id": id_, "type": type_}
    if name:
        n["name"] = name
    t = xf(translate, rotate)
    if t:
        n["transform"] = t
    if color:
        n["color"] = color
    for k, v in params.items():
        if isinstance(v, (int, float)) and not isinstance(v, bool) and k != "count":
            v = num(v)
        n[k] = v
    return n


def box(id_, name, size, round_=0, **kw):
    extra = {"round": round_} if round_ else {}
    return node(id_, "box", name, size=vec(*size), **extra, **kw)


def cylinder(id_, name, radius, height, **kw):
    return node(id_, "cylinder", name, radius=radius, height=height, **kw)


def cone(id_, name, r_bottom, r_top, height, **kw):
    return node(id_, "cone", name, radius_bottom=r_bottom, radius_top=r_top,
                height=height, **kw)


def op(id_, type_, name, children, **kw):
    return node(id_, type_, name, children=children, **kw)


def document(name, feature_size, root):
    return {
        "format": "kerf",
        "version": 1,
        "units": "mm",
        "name": name,
        "settings": {"feature_size": feature_size},
        "root": root,
    }


def floor_halfspace(id_):
    """The solid z >= 0: trims the feet of tilted legs flat on the floor."""
    return node(id_, "halfspace", "Floor plane (keep z >= 0)",
                normal=[0, 0, -1], offset=0)


# ---------------------------------------------------------------------------
# 1. Side chair
# ---------------------------------------------------------------------------

def arc_band_profile(radius, thickness, half_chord, points_per_arc=16):
    """A thick circular arc in the XY plane, bowed towards +Y.

    The band's centre line has radius `radius` and runs from x = -half_chord to
    x = +half_chord; its centre of curvature lies on the -Y side, so the band is
    concave towards -Y (towards the sitter).  The ends are radial cuts and the
    centre line's end points lie on y = 0, so the middle bows back by the
    sagitta.  Outer arc left to right, then inner arc right to left: a simple
    polygon with 2 * points_per_arc vertices, first point not repeated.
    """
    phi_max = math.asin(half_chord / radius)
    y0 = radius * math.cos(phi_max)  # centre of curvature at (0, -y0)
    pts = []
    n = points_per_arc - 1
    r_out, r_in = radius + thickness / 2, radius - thickness / 2
    for i in range(points_per_arc):          # outer arc, left to right
        phi = -phi_max + 2 * phi_max * i / n
        pts.append([num(r_out * math.sin(phi)), num(r_out * math.cos(phi) - y0)])
    for i in range(points_per_arc):          # inner arc, right to left
        phi = phi_max - 2 * phi_max * i / n
        pts.append([num(r_in * math.sin(phi)), num(r_in * math.cos(phi) - y0)])
    return pts, radius - y0


def side_chair():
    seat_top = 450.0
    seat_t = 22.0
    seat_bottom = seat_top - seat_t
    seat_w, seat_d = 450.0, 460.0
    seat_y0, seat_y1 = -240.0, 220.0           # front edge, back edge
    leg_x = 190.0                               # leg centre lines at x = +-190
    front_y = -205.0
    front_r_foot, front_r_top = 14.0, 20.0
    front_h = seat_bottom + 2.0                 # runs 2 mm into the seat

    # Rear legs continue up as the back posts, leaning back by `lean` degrees.
    lean = 4.0
    rear_y_foot = 175.0
    total_h = 880.0
    post_len = total_h / math.cos(math.radians(lean))
    s, c = math.sin(math.radians(lean)), math.cos(math.radians(lean))

    def on_post(d, x=0.0, dy=0.0):
        """Point at distance d along the back-post axis (from the foot)."""
        return (x, rear_y_foot + d * s + dy, d * c)

    def post_y_at_z(z):
        return rear_y_foot + z * math.tan(math.radians(lean))

    tilt = (-lean, 0, 0)  # Rx(-lean) turns local +Z to (0, sin, cos): leans back

    apron_h, apron_t = 70.0, 20.0
    apron_z = seat_bottom - apron_h / 2 + 1.0   # 1 mm into the seat
    rear_y_apron = post_y_at_z(apron_z)
    stretcher_z = 160.0
    rear_y_str = post_y_at_z(stretcher_z)

    # --- one side (x > 0), mirrored to the other side ---
    front_leg = cone("front-leg-r", "Front leg (tapered)", front_r_foot, front_r_top,
                     front_h, translate=(leg_x, front_y, front_h / 2))
    back_post = cone("back-post-r", "Rear leg / back post (tapered)", 15.0, 12.0,
                     post_len, translate=on_post(post_len / 2, leg_x), rotate=tilt)
    side_len = rear_y_apron - front_y
    side_apron = box("side-apron-r", "Side apron", (apron_t, side_len, apron_h),
                     round_=2, translate=(leg_x - 5, (front_y + rear_y_apron) / 2, apron_z))
    str_len = rear_y_str - front_y
    side_stretcher = cylinder("side-stretcher-r", "Side stretcher", 9.0, str_len,
                              translate=(leg_x, (front_y + rear_y_str) / 2, stretcher_z),
                              rotate=(90, 0, 0))
    sides = op("legs-and-sides", "mirror", "Legs and side frames (mirrored left/right)",
               [op("right-side", "union", "Right side",
                   [front_leg, back_post, side_apron, side_stretcher])],
               normal=[1, 0, 0], offset=0)

    # --- seat and the front/back aprons ---
    seat = box("seat", "Seat", (seat_w, seat_d, seat_t), round_=6,
               translate=(0, (seat_y0 + seat_y1) / 2, seat_top - seat_t / 2), color=OAK)
    front_apron = box("front-apron", "Front apron", (2 * leg_x, apron_t, apron_h),
                      round_=2, translate=(0, front_y + 5, apron_z))
    back_apron = box("back-apron", "Back apron", (2 * leg_x, apron_t, apron_h),
                     round_=2, translate=(0, rear_y_apron - 3, apron_z))

    # --- curved back: crest rail, lower back rail and spindles ---
    rail_r, rail_t, half_chord = 900.0, 22.0, 196.0
    profile, sagitta = arc_band_profile(rail_r, rail_t, half_chord)
    crest_h, crest_d = 70.0, 795.0           # height, distance along the post axis
    lower_h, lower_d = 40.0, 530.0
    crest = node("crest-rail", "extrude", "Curved crest rail",
                 translate=on_post(crest_d, dy=-4), rotate=tilt,
                 profile=profile, height=crest_h)
    lower = node("lower-back-rail", "extrude", "Curved lower back rail",
                 translate=on_post(lower_d, dy=-4), rotate=tilt,
                 profile=profile, height=lower_h)
    # Spindles sit on the arc: between x = -90 and 90 its centre line is
    # 16.8 .. 21.2 mm behind the ends, so y = 19 keeps them inside the band.
    sp_bottom, sp_top = lower_d, crest_d     # centre to centre of the rails
    sp_len = sp_top - sp_bottom
    spindles = op("spindles", "array", "Back spindles (5 at 45 mm)",
                  [cylinder("spindle", "Spindle", 7.0, sp_len,
                            translate=(-90, 19, 0))],
                  count=[5, 1, 1], step=[45, 0, 0],
                  translate=on_post((sp_bottom + sp_top) / 2, dy=-4), rotate=tilt)

    frame = op("frame", "union", "Chair frame (blended joints)",
               [seat, sides, front_apron, back_apron, crest, lower, spindles],
               blend=4, color=BEECH)

    # --- dowel holes: 8 mm, 30 deep from the seat top into each front leg ---
    dowel_depth = 30.0
    dowels = op("dowel-holes", "mirror", "Leg dowel holes (mirrored)",
                [cylinder("dowel-hole-r", "Dowel hole 8 mm x 30", 4.0, dowel_depth + 1,
                          translate=(leg_x, front_y, seat_top - dowel_depth / 2 + 0.5))],
                normal=[1, 0, 0], offset=0)

    body = op("chair-body", "difference", "Chair body", [frame, dowels])
    root = op("root", "intersection", "Side chair", [body, floor_halfspace("floor")])
    return document("Side chair", 0.5, root)


# ---------------------------------------------------------------------------
# 2. Bookshelf side panel
# ---------------------------------------------------------------------------

def bookshelf_side():
    t, depth, height = 18.0, 300.0, 1800.0
    # Panel occupies x in [-9, 9] (inner face x = +9), y in [0, 300] (front
    # edge y = 0), z in [0, 1800].
    panel = box("panel", "Side panel 18 x 300 x 1800", (t, depth, height),
                round_=1, translate=(0, depth / 2, height / 2), color=OAK)

    eps = 1.0  # cutters overshoot the surfaces they open through
    # Back-panel groove: 6.5 wide x 9 deep, 10 mm in from the back edge, full height.
    g_w, g_d, g_in = 6.5, 9.0, 10.0
    groove = box("back-groove", "Back panel groove 6.5 x 9",
                 (g_d + eps, g_w, height + 2 * eps),
                 translate=(t / 2 - g_d / 2 + eps / 2, depth - g_in - g_w / 2, height / 2))

    # Stopped dados for the fixed bottom and top shelves (18 wide, 8 deep),
    # stopping 10 mm short of the front edge.
    d_d, d_stop = 8.0, 10.0
    dado_len = depth - d_stop + eps
    bottom_z, top_z = 80.0, 1762.0  # shelf centre heights
    dados = [
        box("dado-bottom", "Bottom shelf dado 18 x 8", (d_d + eps, dado_len, t),
            translate=(t / 2 - d_d / 2 + eps / 2, d_stop + dado_len / 2, bottom_z)),
        box("dado-top", "Top shelf dado 18 x 8", (d_d + eps, dado_len, t),
            translate=(t / 2 - d_d / 2 + eps / 2, d_stop + dado_len / 2, top_z)),
    ]

    # Toe kick below the bottom shelf: 60 back from the front, 70 high.
    kick = box("toe-kick", "Toe kick notch 60 x 70", (t + 2 * eps, 60 + eps, 70 + eps),
               translate=(0, (60 - eps) / 2, (70 - eps) / 2))

    # Shelf-pin holes: 5 mm diameter, 12 deep from the inner face, two columns
    # 37 mm in from the front and 37 mm in front of the groove, 32 mm pitch.
    pin_depth = 12.0
    first_z = 160.0
    n_holes = 47                          # 160 .. 1632
    col_front = 37.0
    col_back = depth - g_in - g_w - 37.0  # 246.5
    pin = cylinder("shelf-pin-hole", "Shelf pin hole 5 x 12", 2.5, pin_depth + eps,
                   translate=(t / 2 - pin_depth / 2 + eps / 2, col_front, first_z),
                   rotate=(0, 90, 0))
    pins = op("shelf-pin-holes", "array", "Shelf pin holes (2 columns, 32 mm pitch)",
              [pin], count=[1, 2, n_holes], step=[0, col_back - col_front, 32])

    root = op("root", "difference", "Bookshelf side panel",
              [panel, groove] + dados + [kick, pins], color=OAK)
    return document("Bookshelf side panel", 1, root)


# ---------------------------------------------------------------------------
# 3. Table top
# ---------------------------------------------------------------------------

def table_top():
    L, W, T = 1600.0, 900.0, 28.0
    # Top occupies z in [0, 28]; the underside is z = 0.
    top = box("top-slab", "Top 1600 x 900 x 28", (L, W, T), round_=8,
              translate=(0, 0, T / 2), color=WALNUT)
    eps = 1.0
    m, m_depth, inset = 40.0, 18.0, 90.0   # 40 x 40 mortise, 18 deep, 90 from the edges
    mortise = box("mortise", "Leg mortise 40 x 40 x 18", (m, m, m_depth + eps),
                  translate=(L / 2 - inset, W / 2 - inset, m_depth / 2 - eps / 2))
    mortises = op("mortises", "mirror", "Leg mortises (mirrored front/back)",
                  [op("mortises-right", "mirror", "Leg mortises (mirrored left/right)",
                      [mortise], normal=[1, 0, 0], offset=0)],
                  normal=[0, 1, 0], offset=0)
    # Pilot holes for the apron fasteners: 4 mm x 15 deep, five along each long side.
    pilot_depth = 15.0
    n, pitch = 5, 250.0
    pilot = cylinder("pilot-hole", "Fastener pilot hole 4 x 15", 2.0, pilot_depth + eps,
                     translate=(-(n - 1) * pitch / 2, W / 2 - inset - 25,
                                pilot_depth / 2 - eps / 2))
    pilots = op("pilot-holes", "mirror", "Fastener pilot holes (mirrored)",
                [op("pilot-row", "array", "Pilot hole row (5 at 250 mm)", [pilot],
                    count=[n, 1, 1], step=[pitch, 0, 0])],
                normal=[0, 1, 0], offset=0)
    root = op("root", "difference", "Table top", [top, mortises, pilots], color=WALNUT)
    return document("Table top", 1, root)


# ---------------------------------------------------------------------------
# 4. Round stool
# ---------------------------------------------------------------------------

def stool():
    seat_r, seat_t, seat_top, edge_r = 175.0, 35.0, 450.0, 6.0
    # A cylinder grown by `edge_r` with an offset: rounded edges, outer size kept.
    seat = op("seat", "offset", "Seat (rounded by offset 6)",
              [cylinder("seat-core", "Seat core", seat_r - edge_r, seat_t - 2 * edge_r)],
              distance=edge_r, translate=(0, 0, seat_top - seat_t / 2), color=CHERRY)

    splay = 8.0
    top_radial = 115.0                   # leg axis at the seat underside
    top_z = seat_top - seat_t + 5.0      # 5 mm into the seat
    leg_len = top_z / math.cos(math.radians(splay))
    tan_s = math.tan(math.radians(splay))

    def axis_radial(z):
        return top_radial + (top_z - z) * tan_s

    legs = []
    for i, az in enumerate((45, 135, 225, 315)):
        r_mid = axis_radial(top_z / 2)
        a = math.radians(az)
        # Rz(az) * Ry(-splay): local +Z leans inwards, towards the stool axis.
        legs.append(cone(f"leg-{i + 1}", f"Leg {i + 1} (splayed {num(splay)} deg)",
                         15.0, 19.0, leg_len,
                         translate=(r_mid * math.cos(a), r_mid * math.sin(a), top_z / 2),
                         rotate=(0, -splay, az)))

    ring_z = 170.0
    ring = node("foot-ring", "torus", "Foot ring stretcher", translate=(0, 0, ring_z),
                major_radius=axis_radial(ring_z), minor_radius=10)
    # Two straight stretchers higher up, joining opposite legs, at different
    # heights so they pass over each other.
    cross = []
    for i, (az, z) in enumerate(((45, 300.0), (135, 320.0))):
        span = 2 * axis_radial(z)
        cross.append(cylinder(f"cross-stretcher-{i + 1}", f"Cross stretcher {i + 1}",
                              9.0, span, translate=(0, 0, z), rotate=(0, 90, az)))

    base = op("base", "union", "Legs and stretchers (blended)", legs + [ring] + cross,
              blend=3, color=ASH)
    body = op("stool-body", "union", "Stool body", [seat, base], blend=4)
    root = op("root", "intersection", "Round stool", [body, floor_halfspace("floor")])
    return document("Round stool", 0.5, root)


# ---------------------------------------------------------------------------
# 5. Cabinet door
# ---------------------------------------------------------------------------

def door_frame():
    W, H, T = 400.0, 600.0, 20.0
    stile_w, rail_w = 60.0, 60.0
    # The door lies on its back: width along X, height along Y, thickness along
    # Z; the back (hinge) face is z = 0, the front face z = 20.
    eps = 1.0
    stiles = [box(f"stile-{side}", f"{side.capitalize()} stile 60 x 600 x 20",
                  (stile_w, H, T), round_=1.5,
                  translate=(sx * (W - stile_w) / 2, 0, T / 2))
              for side, sx in (("left", -1), ("right", 1))]
    rail_len = W - 2 * stile_w + 2.0       # 1 mm into each stile
    rails = [box(f"rail-{side}", f"{side.capitalize()} rail 280 x 60 x 20",
                 (rail_len, rail_w, T), round_=1.5,
                 translate=(0, sy * (H - rail_w) / 2, T / 2))
             for side, sy in (("top", 1), ("bottom", -1))]
    members = op("frame-members", "union", "Stiles and rails", stiles + rails)

    # Panel groove: 6 wide, 10 deep into the inner edge of every member, centred
    # in the thickness.
    g_w, g_d = 6.0, 10.0
    open_w, open_h = W - 2 * stile_w, H - 2 * rail_w      # 280 x 480 opening
    groove = box("panel-groove", "Panel groove 6 x 10",
                 (open_w + 2 * g_d, open_h + 2 * g_d, g_w), translate=(0, 0, T / 2))

    # Hinge cups: 35 mm diameter, 13 deep from the back, centre 22.5 from the
    # hinge edge, 100 mm from top and bottom.
    cup_depth = 13.0
    cup = cylinder("hinge-cup", "Hinge cup 35 x 13", 17.5, cup_depth + eps,
                   translate=(-W / 2 + 22.5, -(H / 2 - 100), cup_depth / 2 - eps / 2))
    cups = op("hinge-cups", "array", "Hinge cup holes (2 at 400 mm)", [cup],
              count=[1, 2, 1], step=[0, H - 200, 0])
    frame = op("frame", "difference", "Door frame", [members, groove, cups], color=CHERRY)

    # Floating panel: a 5 mm tongue in the 6 mm groove (2 mm expansion gap at
    # the groove bottom) and a pillowed field made with an offset.
    tongue = box("panel-tongue", "Panel tongue 5 mm",
                 (open_w + 2 * g_d - 4, open_h + 2 * g_d - 4, 5.0), translate=(0, 0, T / 2))
    pillow = 5.0
    field = op("panel-field", "offset", "Pillowed field (offset 5)",
               [box("field-core", "Field core", (open_w - 40 - 2 * pillow,
                                                 open_h - 40 - 2 * pillow, 2.0))],
               distance=pillow, translate=(0, 0, T / 2 + 1.0))
    panel = op("panel", "union", "Floating panel", [tongue, field], blend=8, color=MAPLE)

    root = op("root", "union", "Cabinet door", [frame, panel])
    return document("Cabinet door 400 x 600", 0.5, root)


EXAMPLES = {
    "side-chair.kerf": side_chair,
    "bookshelf-side.kerf": bookshelf_side,
    "table-top.kerf": table_top,
    "stool.kerf": stool,
    "door-frame.kerf": door_frame,
}


def to_json(value, indent=0):
    """json.dumps with a 2-space indent, but short lists of numbers (sizes,
    transforms, profile points) kept on one line for readability."""
    pad, inner = "  " * indent, "  " * (indent + 1)
    if isinstance(value, dict):
        if not value:
            return "{}"
        items = [f"{inner}{json.dumps(k)}: {to_json(v, indent + 1)}" for k, v in value.items()]
        return "{\n" + ",\n".join(items) + "\n" + pad + "}"
    if isinstance(value, list):
        if all(isinstance(v, (int, float)) for v in value):
            return "[" + ", ".join(json.dumps(v) for v in value) + "]"
        if not value:
            return "[]"
        items = [inner + to_json(v, indent + 1) for v in value]
        return "[\n" + ",\n".join(items) + "\n" + pad + "]"
    return json.dumps(value)


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    out = sys.argv[1] if len(sys.argv) > 1 else os.path.join(here, "..", "resources", "examples")
    os.makedirs(out, exist_ok=True)
    for fname, make in EXAMPLES.items():
        path = os.path.join(out, fname)
        with open(path, "w", encoding="utf-8") as f:
            doc = make()
            text = to_json(doc)
            assert json.loads(text) == doc
            f.write(text + "\n")
        print(path)


if __name__ == "__main__":
    main()
