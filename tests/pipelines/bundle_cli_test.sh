#!/usr/bin/env bash
# The bundle tool as a pipeline calls it: exit codes, messages that name the file and the
# problem, reports, and nothing written by a failed run.
HERE=$(cd "$(dirname "$0")" && pwd)
# shellcheck source=tests/cli/lib.sh
source "$HERE/../cli/lib.sh"
# shellcheck source=tests/pipelines/tiny.sh
source "$HERE/tiny.sh"
require_blender_data
B="$BIN/bundle"
expect_exit 2 "no mode" -- "$B"
expect_exit 0 "--help" -- "$B" pack --help
expect_exit 2 "pack without --file" -- "$B" pack --kind fabric --id x -o "$WORK/b"
expect_exit 2 "unknown kind" -- "$B" pack --kind sofa --id x --file albedo=a.png -o "$WORK/b"
expect_exit 2 "fabric-maps: negative relief" -- "$B" fabric-maps --albedo-texture "$TEXTURE" --relief-texels -1 -o "$WORK/m"

expect_exit 0 "fabric-maps" -- "$B" fabric-maps --albedo-texture "$TEXTURE" --max-size-px 64 \
    --thumbnail-px 16 --name "Weave" --tile-size-m 0.04 -o "$WORK/m" --report "$WORK/m.json"
expect_true "maps: 64 px albedo, derived normals, 16 px thumbnail" -- \
    jq -e '.metrics.width_px == 64 and .metrics.normal_source == "derived" and .metrics.thumbnail_width_px == 16 and .metrics.tile_size_m == 0.04' "$WORK/m.json"
printf 'specular = "lambert"\n' > "$WORK/mat.toml"
files=(--file "albedo=$WORK/m/albedo.png" --file "normal=$WORK/m/normal.png"
    --file "thumbnail=$WORK/m/thumbnail.png" --file "material=$WORK/mat.toml@material.toml")
expect_exit 2 "pack: unknown role is a usage error" -- "$B" pack --kind fabric --id w "${files[@]}" --file "sparkle=$WORK/mat.toml" -o "$WORK/b"
expect_stderr "'sparkle' is not a fabric role (roles: albedo" "names the role and the roles a fabric may hold"
expect_exit 1 "pack: missing source" -- "$B" pack --kind fabric --id w "${files[@]}" --file "brdf_sh_table=$WORK/nope.bin" -o "$WORK/b"
expect_stderr "nope.bin: not found" "names the file"
expect_true "failed packs leave nothing" -- test ! -e "$WORK/b/fabrics/w"
expect_exit 2 "pack: bad id (a usage error, found by the parser)" -- "$B" pack --kind fabric --id "../w" "${files[@]}" -o "$WORK/b"
expect_stderr "--id: '../w'" "names the option and the id"
expect_true "a refused id makes no folder" -- test ! -e "$WORK/b/w"
expect_exit 0 "pack" -- "$B" pack --kind fabric --id w --name "Weave" "${files[@]}" \
    --property sh_bands=3 --property note=plain -o "$WORK/b" --report "$WORK/pack.json"
# The console summary (docs/report.md) says what was packed, with the report's counts.
expect_stderr "bundle: packed: fabric w: " "summary: kind and id"
expect_summary_number "summary: file count is the report's" "packed: .*: ([0-9]+) files?," "$WORK/pack.json" '.metrics.file_count'
expect_summary_number "summary: bytes are the report's" "packed: .*, ([0-9]+) bytes" "$WORK/pack.json" '.metrics.total_bytes'
expect_true "manifest properties typed (3 is a number, plain a string)" -- \
    jq -e '.properties.sh_bands == 3 and .properties.note == "plain"' "$WORK/b/fabrics/w/manifest.json"
expect_exit 0 "verify" -- "$B" verify "$WORK/b" --report "$WORK/v.json"
expect_true "verify report lists the bundle" -- jq -e '.metrics.verified == 1 and .metrics.failed == 0' "$WORK/v.json"
expect_stderr "bundle: verified: OK, 1 bundle, " "summary: OK and one bundle, in the singular"
expect_summary_number "summary: verified count is the report's" "verified: OK, ([0-9]+) bundles?," "$WORK/v.json" '.metrics.verified'
expect_exit 0 "index" -- "$B" index "$WORK/b" --report "$WORK/i.json"
expect_stderr "bundle: catalogue: 1 bundle (1 fabric, 0 devices) in " "summary: the catalogue's bundles by kind"
expect_summary_number "summary: catalogue count is the report's" "catalogue: ([0-9]+) bundles? " "$WORK/i.json" '.metrics.entries | length'
expect_true "catalogue row" -- test "$(sqlite3 "$WORK/b/catalog.sqlite" 'SELECT name FROM fabrics')" = "Weave"

cp -r "$WORK/b" "$WORK/c"
printf 'x' >> "$WORK/c/fabrics/w/material.toml"
expect_exit 1 "verify: a grown file" -- "$B" verify "$WORK/c" --report "$WORK/v2.json"
expect_stderr "material.toml: .* bytes, the manifest says" "names the file and the sizes"
expect_true "report says failed" -- jq -e '.status == "failed" and .metrics.failed == 1' "$WORK/v2.json"
expect_exit 1 "index refuses a broken bundle" -- "$B" index "$WORK/c"

# One rule set for verify and index: a bundle in a root sits in a folder named by its id.
cp -r "$WORK/b" "$WORK/r"
mv "$WORK/r/fabrics/w" "$WORK/r/fabrics/renamed"
expect_exit 1 "verify: folder name is not the id" -- "$B" verify "$WORK/r"
expect_stderr "renamed: folder name differs from the manifest's id 'w'" "verify names the folder and the id"
expect_exit 1 "index: the same rule" -- "$B" index "$WORK/r"
expect_stderr "folder name differs from the manifest's id 'w'" "index says the same"
# The catalogue never lands inside a bundle.
expect_exit 2 "index -o inside a bundle" -- "$B" index "$WORK/b" -o "$WORK/b/fabrics/w/catalog.sqlite"
expect_stderr "where the bundles are" "says why"
expect_exit 0 "the bundle is untouched" -- "$B" verify "$WORK/b" -q
# A bundle folder that is a symlink out of the root: refused by verify (the root or the folder)
# and index, naming the link; every file inside it is intact, so only its place can tell.
cp -r "$WORK/b" "$WORK/l"
rm "$WORK/l/catalog.sqlite"
mkdir -p "$WORK/away"
mv "$WORK/l/fabrics/w" "$WORK/away/w"
ln -s "$WORK/away/w" "$WORK/l/fabrics/w"
expect_exit 0 "the moved-out folder alone is a valid bundle" -- "$B" verify "$WORK/away/w" -q
expect_exit 1 "verify: a root holding a bundle linked from outside" -- "$B" verify "$WORK/l"
expect_stderr "l/fabrics/w: resolves through a symlink to $WORK/away/w, outside the bundle root" "names the link, its target and the problem"
expect_exit 1 "verify: the linked folder itself" -- "$B" verify "$WORK/l/fabrics/w"
expect_stderr "outside the bundle root" "the same rule"
expect_exit 1 "index: the same rule" -- "$B" index "$WORK/l" --report "$WORK/li.json"
expect_stderr "l/fabrics/w: resolves through a symlink to $WORK/away/w" "index names it"
expect_true "index wrote no catalogue" -- test ! -e "$WORK/l/catalog.sqlite"
# Nothing pack or index writes leaves the root through a link: a linked bundle folder (pack
# would replace it), a linked kind folder (pack's staging folder would go there), a catalogue
# path through a linked folder. Each refused before any work, the target untouched.
before=$(cd "$WORK/away" && find . -type f -exec sha256sum {} + | sort)
expect_exit 1 "pack onto a bundle folder linked out of the root" -- "$B" pack --kind fabric --id w "${files[@]}" -o "$WORK/l"
expect_stderr "fabrics/w: resolves through a symlink" "names the link"
rm "$WORK/l/fabrics/w"
mv "$WORK/l/fabrics" "$WORK/away/fabrics"
ln -s "$WORK/away/fabrics" "$WORK/l/fabrics"
expect_exit 1 "pack into a kind folder linked out of the root" -- "$B" pack --kind fabric --id w3 "${files[@]}" -o "$WORK/l"
expect_stderr "l/fabrics: resolves through a symlink to $WORK/away/fabrics, outside the bundle root" "names the kind folder"
expect_exit 1 "index of a root whose fabrics/ is linked out" -- "$B" index "$WORK/l"
expect_stderr "l/fabrics: resolves through a symlink" "index names it"
expect_exit 1 "verify of that root" -- "$B" verify "$WORK/l"
expect_stderr "l/fabrics: resolves through a symlink" "verify names it"
rm "$WORK/l/fabrics" && mkdir "$WORK/l/fabrics"
ln -s "$WORK/away" "$WORK/l/out"
expect_exit 1 "index -o through a folder linked out of the root" -- "$B" index "$WORK/l" -o "$WORK/l/out/catalog.sqlite"
expect_stderr "l/out: resolves through a symlink to $WORK/away" "names the linked folder"
expect_true "nothing was written out of the root" -- test "$(cd "$WORK/away" && find . -type f -exec sha256sum {} + | sort)" = "$before" -a ! -e "$WORK/away/catalog.sqlite" -a -z "$(find "$WORK/away" -name '.w3*')"
# A folder given as a file is named as such.
mkdir -p "$WORK/afolder"
expect_exit 2 "pack: a folder as --file" -- "$B" pack --kind fabric --id w2 "${files[@]}" \
    --file "brdf_sh_table=$WORK/afolder@brdf/table.bin" -o "$WORK/b"
expect_stderr "afolder is a folder; a bundle lists files" "names the folder"

# A reader never sees a half-replaced bundle: verify in a loop while pack replaces the bundle
# with another content in a loop (bounded: 40 packs); every verify passes.
cp "$WORK/mat.toml" "$WORK/mat2.toml"
printf '# another content\n' >> "$WORK/mat2.toml"
(
    for i in $(seq 1 40); do
        m="$WORK/mat.toml"
        [ $((i % 2)) -eq 0 ] && m="$WORK/mat2.toml"
        "$B" pack --kind fabric --id w --name "Weave" --file "albedo=$WORK/m/albedo.png" \
            --file "normal=$WORK/m/normal.png" --file "thumbnail=$WORK/m/thumbnail.png" \
            --file "material=$m@material.toml" -o "$WORK/b" -q || exit 1
    done
) &
packer=$!
bad=0
runs=0
while kill -0 "$packer" 2>/dev/null; do
    runs=$((runs + 1))
    "$B" verify "$WORK/b/fabrics/w" -q 2>>"$WORK/mixed.err" || bad=$((bad + 1))
done
wait "$packer"
expect_true "the repack loop finished" -- test $? -eq 0
if [ "$bad" -eq 0 ]; then pass "verify during 40 repacks: $runs runs, none saw a mixture"; else
    fail "verify during repacks: $bad of $runs failed"; head -5 "$WORK/mixed.err"; fi
finish
