# bake-catalog: every fabric and device of a catalogue folder into verified bundles, the SQLite
# catalogue, and the validation report (every fabric under every environment), as a Snakemake
# workflow. Run it through pipelines/bake-catalog.sh (it sets the flags below); docs/pipelines.md.
#
#   snakemake -s pipelines/bake-catalog.smk --directory OUT --config catalog=DIR bin=DIR -j N
#
# Incremental by content: when the workflow is loaded, each job's inputs (the fabric's folder,
# the textures its fabric.toml names, the environment maps, the configs, the pipeline scripts
# and the tool binaries) are hashed (SHA-256) into a key file under OUT/keys/, rewritten only
# when its content changes. Rules depend on key files, so a touched but unchanged input rebuilds
# nothing, and a changed one rebuilds exactly the jobs that read it.
# Safe to interrupt: every tool and bundle writes atomically, each job's declared output is
# written last, and Snakemake reruns the jobs that were running when it was killed
# (--rerun-incomplete); finished jobs are not redone.
# What is on disk: the index and the report list exactly the fabrics, devices and environments
# of the catalogue folder now; before they run, what a removed (or renamed) one left in OUT is
# removed (prune_removed), and keys/catalog.key, their input, changes with the listing.
import glob
import hashlib
import os
import shlex
import shutil
import sys
import tomllib

from snakemake.exceptions import WorkflowError

ROOT = os.path.abspath(os.path.join(workflow.basedir, ".."))
sys.path.insert(0, os.path.join(ROOT, "pipelines"))
import catalog_quality  # noqa: E402  (beside this file)
CAT = os.path.abspath(config["catalog"])
BIN = os.path.abspath(config.get("bin", os.path.join(ROOT, "build", "bin")))
OUT = os.getcwd()  # --directory OUT
PIPE = os.path.join(ROOT, "pipelines")
VALIDATE_CONFIG = os.path.abspath(config.get("validate_config", os.environ.get(
    "VALIDATE_RENDER_CONFIG", os.path.join(ROOT, "configs", "pipelines", "validate.toml"))))


def sha256_file(path):
    h = hashlib.sha256()
    with open(path, "rb") as f:
        for block in iter(lambda: f.read(1 << 20), b""):
            h.update(block)
    return h.hexdigest()


def write_key(name, text):
    """Writes OUT/keys/<name>.key holding `text`; rewrites it only when the text changes, so its
    mtime moves only with content. Returns its path."""
    key = os.path.join(OUT, "keys", name + ".key")
    if os.path.exists(key):
        with open(key) as f:
            if f.read() == text:
                return key
    os.makedirs(os.path.dirname(key), exist_ok=True)
    with open(key + ".tmp", "w") as f:
        f.write(text)
    os.replace(key + ".tmp", key)
    return key


def content_key(name, paths):
    """Writes OUT/keys/<name>.key listing the SHA-256 of every path (files, or folders walked
    in sorted order), through write_key. Returns its path."""
    lines = []
    for p in paths:
        if os.path.isdir(p):
            for d, dirs, files in os.walk(p):
                dirs.sort()
                for f in sorted(files):
                    q = os.path.join(d, f)
                    lines.append(f"{sha256_file(q)}  {os.path.relpath(q, p)}")
        elif os.path.isfile(p):
            lines.append(f"{sha256_file(p)}  {os.path.basename(p)}")
        else:
            raise WorkflowError(f"bake-catalog: {p}: not found (needed by {name})")
    return write_key(name, "\n".join(lines) + "\n")


def folders(sub):
    d = os.path.join(CAT, sub)
    if not os.path.isdir(d):
        return []
    return sorted(n for n in os.listdir(d) if not n.startswith(".") and os.path.isdir(os.path.join(d, n)))


def tool(name):
    return os.path.join(BIN, name)


def script(name):  # a pipeline script and the lib.sh it sources: a change to either rebuilds
    return [os.path.join(PIPE, name), os.path.join(PIPE, "lib.sh")]


# The catalogue's own settings: environments (globs, relative to the catalogue folder).
settings = {}
if os.path.isfile(os.path.join(CAT, "catalog.toml")):
    with open(os.path.join(CAT, "catalog.toml"), "rb") as f:
        settings = tomllib.load(f)
ENVS = {}
for pattern in settings.get("environments", []):
    for p in sorted(glob.glob(os.path.join(CAT, pattern))):
        ENVS[os.path.splitext(os.path.basename(p))[0]] = p
if config.get("environments"):  # --config environments=city,night: a subset
    wanted = str(config["environments"]).split(",")
    ENVS = {k: v for k, v in ENVS.items() if k in wanted}

# Keys, computed now (this is what makes the workflow incremental by content).
FABRICS = folders("fabrics")
# Captured-BTF fabrics (weave.toml + capture.toml, no btf/ folder): their capture is a job of
# its own, keyed by the weave, the capture options and render, so a new material or bake option
# does not redo it.
CAPTURED = []
for fid in FABRICS:
    fdir = os.path.join(CAT, "fabrics", fid)
    with open(os.path.join(fdir, "fabric.toml"), "rb") as f:
        maps = tomllib.load(f)
    textures = [os.path.join(fdir, maps[k]) for k in ("albedo-texture", "normal-texture") if k in maps]
    if (not os.path.isdir(os.path.join(fdir, "btf")) and os.path.isfile(os.path.join(fdir, "weave.toml"))
            and os.path.isfile(os.path.join(fdir, "capture.toml"))):
        CAPTURED.append(fid)
        content_key("capture-" + fid, [os.path.join(fdir, "weave.toml"), os.path.join(fdir, "capture.toml"),
                                       tool("render")] + script("capture-btf.sh"))
    content_key("fabric-" + fid, [fdir] + textures + [
        os.path.join(ROOT, "configs", "brdf-sh-bake.toml"), os.path.join(ROOT, "configs", "btf-pca.toml"),
        tool("bundle"), tool("brdf-sh-bake"), tool("btf-pca")] + script("bake-fabric.sh"))

DEVICES = []
for did in folders("devices"):
    ddir = os.path.join(CAT, "devices", did)
    with open(os.path.join(ddir, "calibrate.toml"), "rb") as f:
        inputs = [os.path.join(ddir, p) for p in tomllib.load(f).get("inputs", [])]
    missing = [p for p in inputs if not os.path.exists(p)]
    if missing:
        print(f"bake-catalog: device {did} skipped: {', '.join(missing)} not found "
              "(../shared/data is not beside the repository)", file=sys.stderr)
        continue
    DEVICES.append(did)
    content_key("device-" + did, [ddir] + inputs + [tool("bundle"), tool("calibrate")] + script("bake-device.sh"))

for env, path in ENVS.items():
    content_key("env-" + env, [path])
content_key("validate", [VALIDATE_CONFIG, tool("render"), tool("bundle"), tool("envmap-project")]
            + script("validate-pair.sh") + [os.path.join(PIPE, "catalog_quality.py")])
# The quality gate of each fabric's pairs ([quality] of catalog.toml, docs/pipelines.md): a key
# per fabric, so changing a threshold validates that fabric's pairs again.
try:
    QUALITY = {fid: catalog_quality.environment(q)
               for fid, q in catalog_quality.load(CAT, FABRICS).items()}
except catalog_quality.QualityError as e:
    raise WorkflowError(f"bake-catalog: {e}")
for fid in FABRICS:
    write_key("quality-" + fid, "".join(f"{k}={v}\n" for k, v in sorted(QUALITY[fid].items())))
content_key("report", script("validate-report.sh"))
content_key("index", [tool("bundle")])
# The listing itself: a fabric, device or environment added, removed or renamed changes this key,
# so the index and the report run again (a removal changes no other input they declare).
ALL_DEVICES = folders("devices")  # with the ones skipped for missing data: their bundles stay
write_key("catalog", "".join(
    [f"fabric {f}\n" for f in FABRICS] + [f"device {d}\n" for d in ALL_DEVICES]
    + [f"environment {e}\n" for e in sorted(ENVS)]))


def prune_removed():
    """Removes from OUT what fabrics, devices and environments no longer in the catalogue folder
    left there: their bundles (unfinished hidden ones too), stamps, keys, work and capture folders
    and validation pairs, and the report when no pair remains. A fabric added back is then baked
    again (its stamp is gone with its bundle). Touches nothing of a current id, so it may run
    beside any job of this run, and beside itself (index and report may prune at once)."""
    def rm(path):
        if os.path.isdir(path) and not os.path.islink(path):
            shutil.rmtree(path, ignore_errors=True)
        else:
            try:
                os.remove(path)
            except FileNotFoundError:
                pass

    def listdir(path):  # [] when absent (or removed meanwhile by the other prune)
        try:
            return os.listdir(path)
        except (FileNotFoundError, NotADirectoryError):
            return []

    def bundle_id(name):  # a bundle folder's id; pack's unfinished ".<id>.tmp-..." folders too
        return name[1:].split(".tmp-")[0] if name.startswith(".") else name

    for kind, keep in (("fabric", set(FABRICS)), ("device", set(ALL_DEVICES))):
        steps = [kind, "capture", "quality"] if kind == "fabric" else [kind]
        root = os.path.join(OUT, "bundles", kind + "s")
        gone = {bundle_id(n) for n in listdir(root)} - keep
        for n in listdir(os.path.join(OUT, "stamps")):
            for step in steps:
                if n.startswith(step + "-") and n.endswith(".json"):
                    gone |= {n[len(step) + 1:-len(".json")]} - keep
        for i in sorted(gone):
            for n in listdir(root):
                if bundle_id(n) == i:
                    rm(os.path.join(root, n))
            for step in steps:
                rm(os.path.join(OUT, "stamps", f"{step}-{i}.json"))
                rm(os.path.join(OUT, "keys", f"{step}-{i}.key"))
            rm(os.path.join(OUT, "work", kind + "s", i))
            if kind == "fabric":
                rm(os.path.join(OUT, "captures", i))
    pairs = os.path.join(OUT, "validate", "pairs")
    for fid in listdir(pairs):
        if fid not in FABRICS:
            rm(os.path.join(pairs, fid))
            continue
        for env in listdir(os.path.join(pairs, fid)):
            if env not in ENVS:
                rm(os.path.join(pairs, fid, env))
    if not (FABRICS and ENVS):  # no pair: no report (rule all asks for none)
        for n in ("index.html", "summary.md", "summary.json", "pairs", "plots"):
            rm(os.path.join(OUT, "validate", n))


# Every job's shell holds a shared lock on OUT/.bake-catalog.jobs, inherited by each process it
# starts, so the lock is held until the job's last process exits, even when Snakemake itself was
# killed: bake-catalog.sh refuses to start while it is held (docs/pipelines.md).
shell.prefix("set -euo pipefail; exec 8>>" + shlex.quote(os.path.join(OUT, ".bake-catalog.jobs")).replace("{", "{{").replace("}", "}}")
             + "; flock -s 8; ")

# The error decomposition (render compare --decompose) runs on each fabric's first environment: it
# costs about as much again as the pair's comparison, and one environment per fabric shows where
# that fabric's error comes from.
DECOMPOSE_ENV = sorted(ENVS)[0] if ENVS else None

# One convergence study of the truth (error against spp), on the first fabric and environment.
FIRST = f"validate/pairs/{FABRICS[0]}/{sorted(ENVS)[0]}/convergence.json" if FABRICS and ENVS else None

# index and report are bookkeeping over what the other jobs wrote (a SQLite index, an HTML page):
# under --cores a `run:` rule that is not local is run by a second Snakemake process, whose
# start-up (~1.5 s, more under load) cost more than the rule; under --slurm they run on the
# submitting node rather than waiting in the queue.
localrules: all, index, report

rule all:
    input:
        "bundles/catalog.sqlite",
        "validate/index.html" if ENVS and FABRICS else [],

rule capture:
    input: "keys/capture-{fid}.key"
    output: "stamps/capture-{fid}.json"
    log: "logs/capture-{fid}.log"
    shell:
        "INLIGHT_BIN={BIN:q} {PIPE}/capture-btf.sh {CAT}/fabrics/{wildcards.fid} captures/{wildcards.fid} > {log} 2>&1"
        " && cp captures/{wildcards.fid}/capture.json {output}.tmp && mv {output}.tmp {output}"

rule fabric:
    input:
        key="keys/fabric-{fid}.key",
        capture=lambda w: [f"stamps/capture-{w.fid}.json"] if w.fid in CAPTURED else [],
    output: "stamps/fabric-{fid}.json"
    log: "logs/fabric-{fid}.log"
    params: btf=lambda w: f"{OUT}/captures/{w.fid}/btf" if w.fid in CAPTURED else ""
    shell:
        "INLIGHT_BIN={BIN:q} {PIPE}/bake-fabric.sh {CAT}/fabrics/{wildcards.fid} {OUT:q} {wildcards.fid} {params.btf} > {log} 2>&1"
        " && cp work/fabrics/{wildcards.fid}/verify.json {output}.tmp && mv {output}.tmp {output}"

rule device:
    input: "keys/device-{did}.key"
    output: "stamps/device-{did}.json"
    log: "logs/device-{did}.log"
    shell:
        "INLIGHT_BIN={BIN:q} {PIPE}/bake-device.sh {CAT}/devices/{wildcards.did} {OUT:q} {wildcards.did} > {log} 2>&1"
        " && cp work/devices/{wildcards.did}/verify.json {output}.tmp && mv {output}.tmp {output}"

# A captured fabric's pairs also shade its raw BTF against the woven geometry (validate-pair.sh
# RAW_BTF WEAVE): the BTF's own error and that of each prefix of the bundle's stream.
rule pair:
    input:
        stamp="stamps/fabric-{fid}.json",
        capture=lambda w: [f"stamps/capture-{w.fid}.json"] if w.fid in CAPTURED else [],
        env="keys/env-{env}.key",
        validate="keys/validate.key",
        quality="keys/quality-{fid}.key",
    output: "validate/pairs/{fid}/{env}/summary.json"
    log: "logs/pair-{fid}-{env}.log"
    params:
        envpath=lambda w: ENVS[w.env],
        decompose=lambda w: 1 if w.env == DECOMPOSE_ENV else 0,
        btf=lambda w: (f"{OUT}/captures/{w.fid}/btf {CAT}/fabrics/{w.fid}/weave.toml" if w.fid in CAPTURED else ""),
        gate=lambda w: " ".join(f"{k}={shlex.quote(v)}" for k, v in sorted(QUALITY[w.fid].items())),
    # A failed quality gate exits 3 after writing the pair's gate_failed.json (not an output:
    # Snakemake removes the failed job's summary.json, so the pair is validated again next run);
    # bake-catalog.sh names the pairs that failed it.
    shell:
        "{params.gate} INLIGHT_BIN={BIN:q} VALIDATE_RENDER_CONFIG={VALIDATE_CONFIG:q} VALIDATE_DECOMPOSE={params.decompose} {PIPE}/validate-pair.sh"
        " bundles/fabrics/{wildcards.fid} {params.envpath:q} validate/pairs/{wildcards.fid}/{wildcards.env} {params.btf} > {log} 2>&1"

rule convergence:
    input: "validate/pairs/{fid}/{env}/summary.json"
    output: "validate/pairs/{fid}/{env}/convergence.json"
    log: "logs/convergence-{fid}-{env}.log"
    shell:
        "INLIGHT_BIN={BIN:q} {PIPE}/validate-convergence.sh validate/pairs/{wildcards.fid}/{wildcards.env} > {log} 2>&1"

rule report:
    input:
        expand("validate/pairs/{fid}/{env}/summary.json", fid=FABRICS, env=list(ENVS)),
        [FIRST] if FIRST else [],
        "keys/report.key",
        "keys/catalog.key",
    output: "validate/index.html", "validate/summary.md"
    log: "logs/report.log"
    run:
        prune_removed()  # validate-report.sh reports every pair in validate/pairs
        shell("{PIPE}/validate-report.sh validate > {log} 2>&1")

rule index:
    input:
        expand("stamps/fabric-{fid}.json", fid=FABRICS),
        expand("stamps/device-{did}.json", did=DEVICES),
        "keys/index.key",
        "keys/catalog.key",
    output: "bundles/catalog.sqlite"
    log: "logs/index.log"
    run:
        prune_removed()  # bundle index lists every bundle under bundles/
        shell("{BIN}/bundle index bundles -o {output} -q --report logs/index.json > {log} 2>&1")
