#!/usr/bin/env bash
# Subdivision cost beside OpenSubdiv's Far in counts that do not depend on machine load: runs one
# subdivision of each bench input under valgrind's callgrind, on our side
# (kernel/examples/subdiv_once.rs: Refiner::new + refine_positions + to_mesh, the half-edge mesh
# built, as the criterion bench's `subdiv/*_total` cases time it) and on Far's
# (osd_bench.cpp `once`: TopologyRefinerFactory::Create + RefineUniform + PrimvarRefiner, as its
# timed total), counting only inside the measured function of each (--toggle-collect), so loading
# the OBJ file and freeing the results are left out. Prints per case the instructions executed
# (Ir) and kcachegrind's classic cycle estimate from the cache simulation,
#   est = Ir + 10 (I1mr + D1mr + D1mw) + 100 (ILmr + DLmr + DLmw),
# ours, Far's and ours over Far; then the cost of semi-sharp creases (creased torus over plain
# torus, ours) in both measures. The caches are fixed (32 KiB 8-way L1s, 8 MiB 16-way LL, 64-byte
# lines) so the figures are the same on any machine; the same binaries give the same counts run
# after run. Counts leave out the kernel's work (page faults), which wall-clock runs include
# (bench_vs_osd.sh).
#
#   bash tests/data/subdiv/callgrind_vs_osd.sh          # from the repository root; ~10 minutes
# Needs valgrind, g++ and libosd-dev (OpenSubdiv 3.5). SKIP_CARGO=1 reuses the built example;
# CARGO_LOCK=FILE runs cargo under `flock FILE`; CASES="ico6_cc ..." picks cases (ico6_cc,
# ico6_loop, torus_cc, torus_semi_cc); KEEP=DIR keeps the callgrind files there (for
# callgrind_annotate). The inputs are the criterion bench's OBJ files in
# target/tmp/subdiv_inputs/, written by the example when missing.
set -euo pipefail
root="$(cd "$(dirname "$0")/../../.." && pwd)"
cd "$root"
target="${CARGO_TARGET_DIR:-$root/target}"
if [ -z "${SKIP_CARGO:-}" ]; then
    ${CARGO_LOCK:+flock "$CARGO_LOCK"} cargo build --release -p blocksmith-kernel --example subdiv_once >&2
fi
ours="$target/release/examples/subdiv_once"
far="$target/tmp/osd_bench"
inputs="$target/tmp/subdiv_inputs"
mkdir -p "$target/tmp"
g++ -std=c++11 -O2 -o "$far" tests/data/subdiv/osd_bench.cpp -losdCPU
for f in ico6 torus100k torus100k_semi; do
    [ -f "$inputs/$f.obj" ] || "$ours" --write-inputs "$inputs"
done
# The programs run in a scratch folder whose path always has the same length (valgrind puts it
# in the environment as PWD), with fixed short names, inputs and an otherwise empty environment,
# so that their stacks (and so copies' alignment and the simulated cache misses) do not depend
# on where the repository lives. KEEP gets the callgrind files at the end.
out="$(mktemp -d /tmp/callgrind_vs_osd.XXXXXXXX)"
trap 'rm -rf "$out"' EXIT
ln -sf "$ours" "$out/ours"
ln -sf "$far" "$out/far"
for f in ico6 torus100k torus100k_semi; do ln -sf "$inputs/$f.obj" "$out/$f.obj"; done

valgrind="$(command -v valgrind)"
# count NAME FUNCTION PROGRAM ARGS...: callgrind counts inside FUNCTION; prints "Ir est".
count() {
    local name="$1" fn="$2"
    shift 2
    (cd "$out" && env -i "$valgrind" --tool=callgrind --cache-sim=yes --I1=32768,8,64 --D1=32768,8,64 \
        --LL=8388608,16,64 --toggle-collect="*$fn*" --callgrind-out-file="$name.callgrind" "$@" \
        >"$name.stdout" 2>"$name.log")
    python3 - "$out/$name.callgrind" <<'PY'
import sys
ev = tot = None
for line in open(sys.argv[1]):
    if line.startswith("events:"):
        ev = line.split()[1:]
    elif line.startswith(("summary:", "totals:")):
        tot = [int(x) for x in line.split()[1:]]
c = dict(zip(ev, tot + [0] * (len(ev) - len(tot))))
est = c["Ir"] + 10 * (c["I1mr"] + c["D1mr"] + c["D1mw"]) + 100 * (c["ILmr"] + c["DLmr"] + c["DLmw"])
print(c["Ir"], est)
PY
}

ratio() { python3 -c "import sys; print(f'{int(sys.argv[1]) / int(sys.argv[2]):.3f}')" "$1" "$2"; }

declare -A IR EST
printf '%-16s %15s %15s %7s %15s %15s %7s\n' case Ir_ours Ir_far ratio est_ours est_far ratio
for c in ${CASES:-ico6_cc ico6_loop torus_cc torus_semi_cc}; do
    case "$c" in
        ico6_cc) scheme=catmark file=ico6 ;;
        ico6_loop) scheme=loop file=ico6 ;;
        torus_cc) scheme=catmark file=torus100k ;;
        torus_semi_cc) scheme=catmark file=torus100k_semi ;;
        *) echo "callgrind_vs_osd: unknown case $c" >&2; exit 2 ;;
    esac
    read -r ir_o est_o < <(count "${c}_ours" blocksmith_subdiv_once_measured ./ours "$scheme" "$file.obj" 3)
    read -r ir_f est_f < <(count "${c}_far" osd_far_once_measured ./far "$scheme" "$file.obj" 3 once)
    if [ -z "${ir_o:-}" ] || [ -z "${ir_f:-}" ]; then
        cat "$out/${c}"_*.log >&2
        echo "callgrind_vs_osd: $c failed" >&2
        exit 1
    fi
    IR[$c]=$ir_o EST[$c]=$est_o
    printf '%-16s %15s %15s %7s %15s %15s %7s\n' "$c" "$ir_o" "$ir_f" "$(ratio "$ir_o" "$ir_f")" \
        "$est_o" "$est_f" "$(ratio "$est_o" "$est_f")"
done
if [ -n "${KEEP:-}" ]; then
    mkdir -p "$KEEP"
    cp "$out"/*.callgrind "$out"/*.log "$KEEP"/
fi
if [ -n "${IR[torus_cc]:-}" ] && [ -n "${IR[torus_semi_cc]:-}" ]; then
    python3 -c 'import sys; a = [int(x) for x in sys.argv[1:]]
print(f"semi-sharp creases cost (creased torus over plain, ours): Ir {100 * (a[1] / a[0] - 1):+.1f} %, est. cycles {100 * (a[3] / a[2] - 1):+.1f} %")' \
        "${IR[torus_cc]}" "${IR[torus_semi_cc]}" "${EST[torus_cc]}" "${EST[torus_semi_cc]}"
fi
