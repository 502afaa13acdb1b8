"""The forged collapse state files of issue 54, as functions of a genuine state's JSON document.

Each forgery takes a state document (a ``dict`` as ``json.loads`` gives it, version 1 or 2) and returns the
forged document (or, for the duplicate key, the forged text). Every one was accepted by ``xcheck verify``
on main a21edb9 (exit 0, "a genuine collapse state"); ``tests/micro/test_state_forgeries.py`` checks that
each now exits 1 (not a collapse state) or 2 (a malformed file). Plain ``dict`` work and arithmetic only,
so that the same functions forge the files of any version of the suite.
"""

from __future__ import annotations

import copy
import json
from typing import Any

Doc = dict[str, Any]


def _copy(doc: Doc) -> Doc:
    return copy.deepcopy(doc)


def live_scaled(doc: Doc, factor: float = 1.03) -> Doc:
    """Every live load times ``factor`` and the load factor divided by it: the same forces, a lower lambda
    (Set 12 claimed at 0.6710)."""
    out = _copy(doc)
    for b in out["blocks"]:
        b["live"] = [factor * x for x in b["live"]]
    out["load_factor"] = doc["load_factor"] / factor
    return out


def far_block(doc: Doc, *, load_factor: float, weight: float = 1e9, zero_forces: bool = False,
              mu: float = 0.75) -> Doc:
    """One more block far away, ``1e5 x 1e4`` on the ground, sliding: its weight sets the force scale
    and its friction's dissipation the power scale, so that the wall's blocks can be claimed at another
    ``load_factor`` (with ``zero_forces``: every contact force of the wall zero). ``weight`` is its dead
    load (1e9, its area at unit weight; or 1e12); ``mu`` its friction coefficient (its live load is
    ``mu / load_factor`` times its weight: with ``mu = load_factor``, its weight, as a wall's block's)."""
    out = _copy(doc)
    lam = float(load_factor)
    out["load_factor"] = lam
    if zero_forces:
        out["normal_forces"] = [0.0] * len(doc["normal_forces"])
        out["shear_forces"] = [0.0] * len(doc["shear_forces"])
    xs = [v[0] for b in doc["blocks"] for v in b["vertices"]]
    x0, width, height = max(xs) + 1e6, 1e5, 1e4
    # sliding at the yield line: lambda * live = mu * weight; the velocity no larger than the wall's rates
    rates = [abs(x) for x in doc["opening_rates"] + doc["slip_rates"]] or [1.0]
    speed = 0.5 * max(rates)
    live = mu * weight / lam
    n_blocks = len(doc["blocks"])
    block = {"vertices": [[x0, 0.0], [x0 + width, 0.0], [x0 + width, height], [x0, height]],
             "centroid": [x0 + width / 2, height / 2], "weight": weight, "dead": [0.0, -weight, 0.0],
             "live": [live, 0.0, 0.0]}
    if doc.get("version") == 2:
        members = [m for b in doc["blocks"] for m in b["members"]]
        block.update(members=[max(members) + 1], thickness=weight / (width * height * doc["unit_weight"]))
    out["blocks"].append(block)
    # the two ground points: n1 + n2 = W; the moment about the centroid: the normals at -+width/2, the
    # shears -mu n at height/2 below it: width/2 (n2 - n1) + height/2 * mu (n1 + n2) ... solved below
    half_w, half_h = width / 2, height / 2
    # moment of point forces (n up, s = -mu n along +x) at (dx, -half_h): dx * n - (-half_h) * s
    #   = dx n + half_h (-mu n) ; sum over the two = 0 (the loads act at the centroid: no moment)
    # n1 (-half_w - half_h mu) + n2 (half_w - half_h mu) = 0, n1 + n2 = W
    a1, a2 = -half_w - half_h * mu, half_w - half_h * mu
    n2 = weight * (-a1) / (a2 - a1)
    n1 = weight - n2
    for x, n in ((x0, n1), (x0 + width, n2)):
        out["points"].append({"blocks": [-1, n_blocks], "position": [x, 0.0], "normal": [0.0, 1.0],
                              "tangent": [1.0, 0.0], "mu": mu})
        out["normal_forces"].append(n)
        out["shear_forces"].append(-mu * n)
        out["opening_rates"].append(0.0)
        out["slip_rates"].append(speed)
        out["contact_states"].append("sliding")
    out["velocities"].append([speed, 0.0, 0.0])
    return out


def bogus_vertex(doc: Doc, *, moment: float = 0.1) -> Doc:
    """One vertex at ``x = 1e9`` added to the first block's outline (the length scale) and a dead-load
    moment of ``moment`` times its weight times its height added to every block at rest, which the
    length scale then hides."""
    out = _copy(doc)
    first = out["blocks"][0]
    verts = first["vertices"]
    ys = [v[1] for v in verts]
    verts.insert(2, [1e9, 0.5 * (min(ys) + max(ys))])
    for b, v in zip(out["blocks"], doc["velocities"], strict=True):
        if v == [0.0, 0.0, 0.0] or max(abs(x) for x in v) < 1e-12:
            h = max(p[1] for p in b["vertices"]) - min(p[1] for p in b["vertices"])
            b["dead"][2] += moment * b["weight"] * h
    return out


def scaled_numbers(doc: Doc, factor: float = 1e-308, load_factor: float = 0.05) -> Doc:
    """Every force of the state (weights, dead and live loads, contact forces) times ``factor`` (1e-308:
    subnormal numbers, below the floor of the old scales), the load factor set to ``load_factor``."""
    out = _copy(doc)
    for b in out["blocks"]:
        b["weight"] *= factor
        b["dead"] = [factor * x for x in b["dead"]]
        b["live"] = [factor * x for x in b["live"]]
        if "floor" in b:
            b["floor"] = [[x, y, factor * q] for x, y, q in b["floor"]]
    out["normal_forces"] = [factor * x for x in doc["normal_forces"]]
    out["shear_forces"] = [factor * x for x in doc["shear_forces"]]
    if "unit_weight" in doc:
        out["unit_weight"] = doc["unit_weight"] * factor
    out["load_factor"] = load_factor
    return out


def toe_moved_inward(b: float = 0.3, h: float = 1.2, mu: float = 0.6, version: int = 1) -> Doc:
    """The rocking block of ``docs/files.md`` (``b x h`` on the ground, lambda = b/h = 0.25) with its toe
    contact moved inward to ``x = 2b/3``: rocking about that point, lambda = b/(3h) = 0.0833."""
    W = b * h
    toe = 2 * b / 3
    lam = (toe - b / 2) / (h / 2)
    doc: Doc = {
        "format": "xcheck-masonry collapse state", "version": version, "friction": "nonassociative",
        "load_factor": lam, "direction": "+x", "source": {"program": "a hand calculation"},
        "blocks": [{"vertices": [[0, 0], [b, 0], [b, h], [0, h]], "centroid": [b / 2, h / 2], "weight": W,
                    "dead": [0, -W, 0], "live": [W, 0, 0]}],
        "points": [{"blocks": [-1, 0], "position": [0, 0], "normal": [0, 1], "tangent": [1, 0], "mu": mu},
                   {"blocks": [-1, 0], "position": [toe, 0], "normal": [0, 1], "tangent": [1, 0], "mu": mu}],
        "normal_forces": [0, W], "shear_forces": [0, -lam * W],
        "velocities": [[h / 2, toe - b / 2, -1]],  # rotation -1 about (toe, 0)
        "opening_rates": [toe, 0], "slip_rates": [0, 0], "contact_states": ["opening", "closed"],
    }
    if version == 2:
        doc["unit_weight"] = 1.0
        doc["blocks"][0].update(members=[0], thickness=1.0)
    return doc


def dead_halved(doc: Doc) -> Doc:
    """Every dead load, contact force and the load factor halved, the weights unchanged: the same
    mechanism in equilibrium at half the load factor."""
    out = _copy(doc)
    for b in out["blocks"]:
        b["dead"] = [0.5 * x for x in b["dead"]]
    out["normal_forces"] = [0.5 * x for x in doc["normal_forces"]]
    out["shear_forces"] = [0.5 * x for x in doc["shear_forces"]]
    out["load_factor"] = 0.5 * doc["load_factor"]
    return out


def relabelled(doc: Doc, other: Doc) -> Doc:
    """``doc``'s state with ``other``'s description of the wall (its ``source`` and, in version 2, its
    ``wall``): Set 14's state labelled as Set 12."""
    out = _copy(doc)
    out["source"] = copy.deepcopy(other.get("source", {}))
    if "wall" in other:
        out["wall"] = copy.deepcopy(other["wall"])
    return out


def friction_relabelled(doc: Doc, f: float) -> Doc:
    """A genuine state of a wall of another friction coefficient, its wall's friction relabelled ``f``
    (``mu = 0.5`` contacts labelled ``f = 0.75``)."""
    out = _copy(doc)
    src = out.get("source", {})
    if "paper_parameters" in src:
        src["paper_parameters"]["f"] = f
    if "wall" in out:
        out["wall"]["friction"] = f
    return out


def duplicate_key(doc: Doc, key: str = "load_factor", first: float | None = None) -> str:
    """The file's text with ``key`` written twice: ``first`` (default: 0.9 of the value) then the real
    one. Python's reader takes the last copy, another reader may take the first."""
    value = doc[key]
    fake = 0.9 * value if first is None else first
    text = json.dumps(doc)
    needle = f'"{key}": {json.dumps(value)}'
    assert needle in text
    return text.replace(needle, f'"{key}": {json.dumps(fake)}, {needle}', 1)


def as_version_1(doc: Doc) -> Doc:
    """A version-2 document as version 1 wrote it (the keys version 1 has, no more)."""
    out = {k: copy.deepcopy(v) for k, v in doc.items() if k in (
        "format", "version", "friction", "load_factor", "direction", "source", "blocks", "points",
        "normal_forces", "shear_forces", "velocities", "opening_rates", "slip_rates", "contact_states")}
    out["version"] = 1
    out["blocks"] = [{k: b[k] for k in ("vertices", "centroid", "weight", "dead", "live")} for b in doc["blocks"]]
    return out
