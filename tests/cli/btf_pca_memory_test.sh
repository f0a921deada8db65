#!/usr/bin/env bash
# btf-pca's hard case "a BTF larger than memory": the images are streamed by view
# group, so peak memory is bounded by one group, not the whole BTF. Two BTFs of the same light
# set and image size, one with 4 views and one with 16 (4x the data), compressed in one run of
# this script: the memory the run adds (the tool's peak RSS over its RSS before compressing,
# its own report) must not grow with the number of groups (k = 1: 4 against 16 groups), nor, out
# of core under a memory budget, with the views in the one group of all views (k = all: 4
# against 16 views, read a block at a time). Held whole, the larger BTF would need 4x.
# jq programs use $-variables inside single quotes on purpose.
# shellcheck disable=SC2016
# shellcheck source=tests/cli/lib.sh
source "$(dirname "$0")/lib.sh"
PCA="$BIN/btf-pca"
MK="$TBIN/inlight_make_test_btf"
# A sanitizer build's resident memory is mostly its own (ASan's quarantine keeps freed blocks,
# up to 256 MiB, and its shadow), so it cannot show what the tool holds.
if ldd "$PCA" 2>/dev/null | grep -q 'lib[at]san'; then
    skip "btf-pca is built with a sanitizer: its peak RSS measures the sanitizer's quarantine, not the tool"
    finish
    exit
fi

# 8 lights and up to 16 views (three theta rings). 256 x 256 px: one view is 8 lights x 3
# channels = 24 float columns of 65536 px, 6 MiB, so the 16-view BTF is 96 MiB as floats and a
# group dominates the memory a run adds.
for i in $(seq 0 7); do echo "$((15 + 15 * (i % 3))) $((i * 45))"; done >"$WORK/lights.txt"
for i in $(seq 0 15); do echo "$((15 + 15 * (i % 3))) $((i * 22))"; done >"$WORK/views16.txt"
head -4 "$WORK/views16.txt" >"$WORK/views4.txt"
for n in 4 16; do
    "$MK" "$WORK/btf$n" 256 256 4 1.0 "$WORK/lights.txt" "$WORK/views$n.txt" || fail "make_test_btf $n views"
done
run() {  # run VIEWS NAME ARGS...: compresses the VIEWS-view BTF, report NAME.json
    local n=$1 name=$2
    shift 2
    "$PCA" compress "$WORK/btf$n" -o "$WORK/$name" --light-directions "$WORK/lights.txt" --view-directions "$WORK/views$n.txt" \
        -c 4 --threads 2 --report "$WORK/$name.json" -q "$@"
}
added() { jq '.metrics.memory | .peak_rss_mib - .rss_before_mib' "$WORK/$1.json"; }
# RATIO = 1.25: what a run keeps per group (V: 24 x 4 floats, its manifest entry) is kilobytes;
# the rest is the allocator keeping freed blocks of earlier groups. 4x the data held whole is 4x.
RATIO=1.25

# k = 1: 4 against 16 groups, each read, fitted and freed in turn.
expect_exit 0 "k = 1, 4 views: 4 groups" -- run 4 g4 -k 1
expect_exit 0 "k = 1, 16 views: 16 groups" -- run 16 g16 -k 1
expect_true "both in core, 4 and 16 groups" -- jq -e --slurpfile a "$WORK/g4.json" \
    '.metrics.memory.fit == "in-core" and .metrics.pca.groups == 16 and $a[0].metrics.pca.groups == 4' "$WORK/g16.json"
a4=$(added g4)
a16=$(added g16)
echo "    memory added: 4 groups $a4 MiB, 16 groups $a16 MiB"
# (> 6 MiB: one group's floats were held, so the figures measure groups, not noise.)
expect_true "16 groups add at most $RATIO x the memory of 4 groups" -- \
    jq -en --argjson a "$a4" --argjson b "$a16" '$a > 6 and $b <= '"$RATIO"' * $a'

# k = all views: one group of 4 against one of 16 views, out of core (one view per block;
# randomized SVD without power iterations: 5 passes over the images), and the 16 views in core.
OOC=(-k 16 --method randomized --power-iterations 0)
expect_exit 0 "one group of 4 views, out of core" -- run 4 o4 "${OOC[@]}" --stream-views 1
expect_exit 0 "one group of 16 views, out of core" -- run 16 o16 "${OOC[@]}" --stream-views 1
expect_exit 0 "one group of 16 views, in core" -- run 16 i16 "${OOC[@]}"
expect_true "the reports say which fit ran" -- jq -e --slurpfile o "$WORK/o16.json" \
    '.metrics.memory.fit == "in-core" and ($o[0].metrics.memory | .fit == "out-of-core" and .stream_views == 1)' "$WORK/i16.json"
o4=$(added o4)
o16=$(added o16)
i16=$(added i16)
echo "    memory added, one group: out of core 4 views $o4 MiB, 16 views $o16 MiB; in core 16 views $i16 MiB"
expect_true "out of core, 16 views add at most $RATIO x the memory of 4 views" -- \
    jq -en --argjson a "$o4" --argjson b "$o16" '$b <= '"$RATIO"' * $a'
# (2: the in-core group of 16 views is 96 MiB of floats, over 4 times one view's block and the
# out-of-core factors; measured here, not estimated.)
expect_true "out of core adds less than half of what the group held whole adds" -- \
    jq -en --argjson a "$o16" --argjson b "$i16" '2 * $a < $b'
finish
