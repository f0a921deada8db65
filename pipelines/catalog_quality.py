"""The quality gate of a catalogue (docs/pipelines.md "Quality gate"): the [quality] table of
catalog.toml, with per-fabric overrides in [quality.fabrics.<id>], read and checked for
bake-catalog (its Snakemake workflow imports it; bake-catalog.sh runs it first so that a bad
table is a usage error, exit 2, before any job):

    [quality]
    warn-de2000 = 1.0        # render compare --warn-de2000 on every image the app can show
    fail-de2000 = 2.0
    warn-mean-rel = 0.1
    fail-mean-rel = 0.2
    gate-modes = ["consistent"]   # render compare --gate-modes (default: both modes)
    [quality.fabrics.velvet]     # this fabric's own thresholds (the others still apply)
    fail-de2000 = 3.0

    python3 pipelines/catalog_quality.py CATALOG    # checks; exit 2 with the message if bad
"""
import math
import os
import sys
import tomllib

THRESHOLDS = ("warn-mean-rel", "fail-mean-rel", "warn-de2000", "fail-de2000")
MODES = ("consistent", "seed")


class QualityError(Exception):
    pass


def _check(where, table, has_fabrics=False):
    """Checks one table's keys and values; returns it as a dict of the known keys."""
    out = {}
    for key, value in table.items():
        if key == "fabrics" and has_fabrics:
            continue
        if key in THRESHOLDS:
            if isinstance(value, bool) or not isinstance(value, (int, float)):
                raise QualityError(f"{where} {key}: expected a number, got {value!r}")
            if not (math.isfinite(value) and value >= 0):
                raise QualityError(f"{where} {key} = {value}: expected a finite number >= 0")
            out[key] = float(value)
        elif key == "gate-modes":
            if (not isinstance(value, list) or not value
                    or any(m not in MODES for m in value)):
                raise QualityError(f"{where} gate-modes = {value!r}: expected a non-empty list "
                                   f"of {', '.join(repr(m) for m in MODES)}")
            out[key] = list(value)
        else:
            raise QualityError(f"{where} {key}: unknown key (known: "
                               f"{', '.join(THRESHOLDS + ('gate-modes',))})")
    return out


def _check_order(where, q):
    for metric in ("mean-rel", "de2000"):
        w, f = q.get("warn-" + metric), q.get("fail-" + metric)
        if w is not None and f is not None and w > f:
            raise QualityError(f"{where}: warn-{metric} {w:g} exceeds fail-{metric} {f:g} (the "
                               "warning threshold must not be above the failure threshold)")


def load(catalog, fabric_ids):
    """The gate of each fabric of `fabric_ids`: {fid: {key: value}} (empty: no gate). Raises
    QualityError naming catalog.toml, the table and the key on a bad value, an unknown key or a
    [quality.fabrics.<id>] of no fabric."""
    path = os.path.join(catalog, "catalog.toml")
    if not os.path.isfile(path):
        return {fid: {} for fid in fabric_ids}
    with open(path, "rb") as f:
        settings = tomllib.load(f)
    quality = settings.get("quality", {})
    if not isinstance(quality, dict):
        raise QualityError(f"{path}: quality: expected a table [quality]")
    base = _check(f"{path}: [quality]", quality, has_fabrics=True)
    _check_order(f"{path}: [quality]", base)
    per = quality.get("fabrics", {})
    if not isinstance(per, dict):
        raise QualityError(f"{path}: [quality] fabrics: expected tables [quality.fabrics.<id>]")
    for fid in per:
        if fid not in fabric_ids:
            raise QualityError(f"{path}: [quality.fabrics.{fid}]: no fabric '{fid}' in "
                               f"{os.path.join(catalog, 'fabrics')}")
    out = {}
    for fid in fabric_ids:
        q = dict(base)
        if fid in per:
            where = f"{path}: [quality.fabrics.{fid}]"
            if not isinstance(per[fid], dict):
                raise QualityError(f"{where}: expected a table")
            q.update(_check(where, per[fid]))
            _check_order(f"{where} over [quality]", q)
        out[fid] = q
    return out


def environment(q):
    """validate-pair.sh's environment variables for one fabric's gate (docs/pipelines.md)."""
    env = {}
    for key in THRESHOLDS:
        if key in q:
            env["VALIDATE_" + key.upper().replace("-", "_")] = repr(q[key])
    if "gate-modes" in q:
        env["VALIDATE_GATE_MODES"] = ",".join(q["gate-modes"])
    return env


def fabric_ids(catalog):
    d = os.path.join(catalog, "fabrics")
    if not os.path.isdir(d):
        return []
    return sorted(n for n in os.listdir(d)
                  if not n.startswith(".") and os.path.isdir(os.path.join(d, n)))


if __name__ == "__main__":
    if len(sys.argv) != 2:
        print("usage: catalog_quality.py CATALOG", file=sys.stderr)
        sys.exit(2)
    try:
        load(sys.argv[1], fabric_ids(sys.argv[1]))
    except (QualityError, tomllib.TOMLDecodeError) as e:
        print(f"bake-catalog: {e}", file=sys.stderr)
        sys.exit(2)
