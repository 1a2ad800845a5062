#!/usr/bin/env bash
# Subdivision speed beside OpenSubdiv's Far on the same inputs: runs the criterion bench
# kernel/benches/subdiv.rs (release; it writes its inputs as OBJ files), builds osd_bench.cpp
# against libosdCPU, times Far on those files, and prints ours over Far for each case, with the
# half-edge mesh built on our side (Refiner + positions + to_mesh) and topology + positions on
# Far's (its uniform refinement), and the cost of semi-sharp creases (creased over plain torus).
#
#   bash tests/data/subdiv/bench_vs_osd.sh            # from the repository root
# Needs g++ and libosd-dev (OpenSubdiv 3.5). Set SKIP_CARGO=1 to reuse the last criterion run.
set -euo pipefail
root="$(cd "$(dirname "$0")/../../.." && pwd)"
cd "$root"
target="${CARGO_TARGET_DIR:-$root/target}"
if [ -z "${SKIP_CARGO:-}" ]; then
    cargo bench --workspace --bench subdiv -- 'subdiv/.*_total' >&2
fi
inputs="$target/tmp/subdiv_inputs"
prog="$target/tmp/osd_bench"
g++ -std=c++11 -O2 -o "$prog" tests/data/subdiv/osd_bench.cpp -losdCPU
est() { # criterion's mean estimate in seconds
    python3 -c 'import json,sys; print(json.load(open(sys.argv[1]))["mean"]["point_estimate"]/1e9)' \
        "$target/criterion/subdiv/$1/new/estimates.json"
}
far() { # Far's median topology + positions in seconds
    "$prog" "$1" "$inputs/$2.obj" 3 7 | sed -n 's/.*total_med_s=\([0-9.e-]*\).*/\1/p'
}
printf '%-22s %10s %10s %7s\n' case ours_s far_s ratio
for c in "cc3_ico6 catmark ico6" "loop3_ico6 loop ico6" "cc3_torus100k catmark torus100k" \
    "cc3_torus100k_semi catmark torus100k_semi"; do
    set -- $c
    ours=$(est "${1}_total")
    theirs=$(far "$2" "$3")
    printf '%-22s %10.4f %10.4f %7.2f\n' "$1" "$ours" "$theirs" "$(python3 -c "print($ours/$theirs)")"
done
plain=$(est cc3_torus100k_total)
semi=$(est cc3_torus100k_semi_total)
printf 'semi-sharp creases cost: %.1f %% (creased torus over plain, ours)\n' \
    "$(python3 -c "print(100*($semi/$plain-1))")"
