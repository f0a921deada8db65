#!/usr/bin/env bash
# skip_reasons.sh CTEST_CONSOLE_LOG LAST_TEST_LOG: after a ctest run, says why each skipped test
# did not run. ctest lists them ("The following tests did not run: ... (Skipped)") without a
# reason; the reason is in each test's output, which ctest keeps in Testing/Temporary/LastTest.log:
# the "skip: ..." lines of the CLI scripts (tests/cli/lib.sh) and the message GoogleTest prints
# for GTEST_SKIP(). Prints nothing when no test was skipped. Ends with ctest's own summary line
# again, so the run still closes on it.
set -uo pipefail
console=$1
log=$2
mapfile -t skipped < <(sed -n '/The following tests did not run:/,/^[^\t ]/p' "$console" |
    sed -nE 's/^[[:space:]]+[0-9]+ - ([^ ]+) \(Skipped\)$/\1/p')
[ ${#skipped[@]} -gt 0 ] || exit 0
echo
echo "Why the skipped tests did not run:"
for name in "${skipped[@]}"; do
    # The test's block in LastTest.log: from "N/M Test: name" to its "<end of output>".
    reasons=$(awk -v name="$name" '
        $0 ~ "^[0-9]+/[0-9]+ Test: " && $3 == name { inside = 1; next }
        inside && /^<end of output>/ { exit }
        inside && sub(/^skip: /, "") { print; next }
        inside && /: Skipped$/ { gtest = 1; next }
        inside && gtest && /^\[  SKIPPED \]/ { gtest = 0; next }
        inside && gtest && NF { print }' "$log" | sort -u | paste -sd ';' | sed 's/;/; /g')
    echo "  $name: ${reasons:-(no reason printed)}"
done
echo
grep -E '^[0-9]+% tests passed, [0-9]+ tests? failed out of [0-9]+' "$console" | tail -n 1
