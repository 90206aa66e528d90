#!/usr/bin/env bash
# Mutation testing of the pool at HEAD (cargo-mutants), and the report made from it:
#
#   pool/mutants.sh            both runs below, then the report (about 40 min on 2 cores)
#   pool/mutants.sh normal     the contract and stress tests against every mutant of pool/src
#   pool/mutants.sh loom       the loom models against the mutants a normal build cannot see
#                              (sync.rs's loom wrappers) and the sleep protocol's survivors
#   pool/mutants.sh report     only rewrite results/pool-mutants.md from the outcomes files
#
# Each run writes results/pool-mutants-RUN.json: the commit it ran at, the machine, the
# command, the wall time, cargo-mutants' counts and every mutant with its outcome (trimmed from
# cargo-mutants' mutants.out/outcomes.json: no local log paths). The report's tables are made
# from those files only, so anyone can check them. Commit the three files together.
#
# Needs `cargo install cargo-mutants` (27.1.0 made the committed files) and python3. Runs on a
# clean pool/ (commit first), so that the commit named in the outcomes is the code mutated.
set -euo pipefail
cd "$(dirname "$0")/.."
what=${1:-all}
out=target/mutants

# run NAME ENV ARGS…: cargo mutants ARGS with the variables ENV ("A=1 B=2"), into $out/NAME.
run() {
    local name=$1 env=$2
    shift 2
    if [ -z "${MUTANTS_DIRTY:-}" ] && ! git diff --quiet HEAD -- pool .cargo/mutants.toml; then
        echo "pool/ has uncommitted changes: commit them first (or MUTANTS_DIRTY=1 for a trial run)" >&2
        exit 2
    fi
    rm -rf "$out/$name"
    mkdir -p "$out/$name"
    local start end commit
    start=$(date +%s) commit=$(git rev-parse --short=7 HEAD)
    # cargo-mutants exits non-zero when some mutants are missed or time out: those are results.
    env $env cargo mutants --output "$out/$name" "$@" || true
    end=$(date +%s)
    [ -f "$out/$name/mutants.out/outcomes.json" ] || { echo "cargo-mutants wrote no outcomes" >&2; exit 1; }
    COMMAND="$env cargo mutants $*" WALL=$((end - start)) COMMIT=$commit \
        MACHINE="$(lscpu | sed -n 's/^Model name: *//p' | head -1), nproc $(nproc)" \
        python3 - "$out/$name/mutants.out/outcomes.json" "results/pool-mutants-$name.json" <<'EOF'
import json, os, sys
raw = json.load(open(sys.argv[1]))
mutants = []
for o in raw["outcomes"]:
    s = o["scenario"]
    if s == "Baseline":
        continue
    m = s["Mutant"]
    mutants.append({
        "file": m["file"],
        "line": m["span"]["start"]["line"],
        "function": (m.get("function") or {}).get("function_name"),
        "mutation": m["name"].split(": ", 1)[1] if ": " in m["name"] else m["name"],
        "outcome": o["summary"],
        "seconds": round(sum(p["duration"] for p in o["phase_results"]), 1),
    })
mutants.sort(key=lambda m: (m["file"], m["line"], m["mutation"]))
kept = {
    "commit": os.environ["COMMIT"],
    "machine": os.environ["MACHINE"],
    "command": os.environ["COMMAND"],
    "cargo_mutants_version": raw["cargo_mutants_version"],
    "start_time": raw["start_time"],
    "end_time": raw["end_time"],
    "wall_seconds": int(os.environ["WALL"]),
    "counts": {k: raw[k] for k in ["total_mutants", "caught", "missed", "timeout", "unviable"]},
    "mutants": mutants,
}
json.dump(kept, open(sys.argv[2], "w"), indent=1)
print(f"{sys.argv[2]}: {kept['counts']}, {kept['wall_seconds']} s")
EOF
}

if [ "$what" = all ] || [ "$what" = normal ]; then
    # The contract and stress tests (debug builds, as cargo-mutants runs them: stress sizes ÷ 20);
    # every wait of a test gives up after 15 s (pool::deadline), so a mutant that makes the pool
    # hang fails a test that names what never happened, instead of reaching the timeout.
    run normal "RAYPOOL_TEST_DEADLINE=15" -p pool -j 1 --timeout 240
fi
if [ "$what" = all ] || [ "$what" = loom ]; then
    # The loom models, on the mutants a normal build cannot see and the sleep protocol's.
    run loom "RUSTFLAGS=--cfg=loom LOOM_MAX_PREEMPTIONS=3" -p pool -j 1 --profile release \
        --timeout 600 -F loom_locks -F anyone_asleep -- --lib --test loom
fi

python3 - <<'EOF'
import json, os, collections
def load(name):
    path = f"results/pool-mutants-{name}.json"
    return json.load(open(path)) if os.path.exists(path) else None
normal, loom = load("normal"), load("loom")

# Verdicts on survivors, reasoned once (by hand) and matched on the mutation's text. A
# survivor with no verdict here is listed as "no verdict": a line no test watches, to look at.
VERDICTS = [
    ("anyone_asleep -> bool with true", "**equivalent**: a pusher that takes the lock and notifies although nobody sleeps costs a lock per push and changes nothing a test can observe; the check exists only to spare that lock (`sleep.rs`)"),
    ("replace > with >= in Sleep::anyone_asleep", "**equivalent**: the same, as a comparison that is always true"),
    ("replace + with * in StealQueue::steal_from_others", "**equivalent**: a thief then starts at its own index, which the next line filters out, so it visits the same victims in the same order"),
    ("replace > with >= in idle_workers_sleep", "**equivalent** in practice: CPU time comes in 10 ms ticks; a sleeping pool reads 0, a spinning one hundreds of ms"),
    ("replace check -> Result<(), String> with Ok(())", "**caught since** by `the_check_with_its_own_deadline_refuses_a_broken_queue_too` (`pool/tests/conformance.rs`, added after the 2026-12-03 run: no test called `check` itself on a broken queue; checked by planting this mutant by hand)"),
    ("sync.rs", "the loom wrappers: a normal build does not compile them; see the loom run"),
]
def verdict(m):
    text = f"{m['file']}: {m['mutation']}"
    return next((v for k, v in VERDICTS if k in text), "no verdict: a line no test watches")

OUT = {"CaughtMutant": "caught", "MissedMutant": "missed", "Timeout": "timeout", "Unviable": "unviable"}
lines = ["# Does the pool's test suite notice a change? Mutation testing with cargo-mutants", "",
 "Written by `pool/mutants.sh` from its outcomes files, `results/pool-mutants-normal.json` and",
 "`results/pool-mutants-loom.json` (every mutant and its outcome): do not edit by hand, rerun",
 "the script. cargo-mutants changes the pool's code one place at a time (a function body",
 "replaced by a default value, an operator swapped) and reruns the tests; a *missed* mutant is",
 "a change no test noticed, a *timeout* one that made the tests run past cargo-mutants' limit.",
 "The earlier runs (2026-12-01, before the pool's files moved) are in",
 "`results/pool-mutants-history.md`.", ""]
lines += ["## Runs", "", "| run | commit | machine | cargo-mutants | started | mutants | caught | missed | timeout | unviable | wall time |",
          "|---|---|---|---|---|---:|---:|---:|---:|---:|---:|"]
for name, r in [("contract + stress tests", normal), ("loom models (the `-F` subset)", loom)]:
    if r is None:
        lines.append(f"| {name} | not run yet | | | | | | | | | |")
        continue
    c = r["counts"]
    lines.append(f"| {name} | {r['commit']} | {r['machine']} | {r['cargo_mutants_version']} | {r['start_time'][:16]} | "
                 f"{c['total_mutants']} | {c['caught']} | {c['missed']} | {c['timeout']} | {c['unviable']} | "
                 f"{r['wall_seconds'] / 60:.0f} min |")
lines += ["", "Commands (each run's exact one is in its outcomes file):", "", "```sh"]
for r in (normal, loom):
    if r: lines.append(r["command"])
lines += ["```", "", "The contract and stress run sets `RAYPOOL_TEST_DEADLINE=15`, so a mutant that makes the",
 "pool hang fails a test naming what never happened within 15 s instead of reaching the",
 "timeout. `.cargo/mutants.toml` keeps the loom models themselves (`mod model`) out.", ""]
if normal:
    lines += ["## Per file (contract + stress tests)", "", "| file | mutants | caught | missed | timeout | unviable |", "|---|---:|---:|---:|---:|---:|"]
    per = collections.OrderedDict()
    for m in normal["mutants"]:
        per.setdefault(m["file"], collections.Counter())[OUT.get(m["outcome"], m["outcome"])] += 1
    for f, c in per.items():
        lines.append(f"| `{f}` | {sum(c.values())} | {c['caught']} | {c['missed']} | {c['timeout']} | {c['unviable']} |")
    lines.append("")
    loom_by = {(m["file"], m["line"], m["mutation"]): OUT.get(m["outcome"], m["outcome"]) for m in (loom or {"mutants": []})["mutants"]}
    surv = [m for m in normal["mutants"] if m["outcome"] in ("MissedMutant", "Timeout")]
    lines += ["## Survivors of the contract and stress tests, and their verdicts", "",
              "| mutant | contract + stress | loom | verdict |", "|---|---|---|---|"]
    for m in surv:
        l = loom_by.get((m["file"], m["line"], m["mutation"]), "not run")
        lines.append(f"| `{m['file']}:{m['line']}`: {m['mutation']} | {OUT[m['outcome']]} | {l} | {verdict(m)} |")
    lines.append("")
if loom:
    lines += ["## The loom run, mutant by mutant", "", "| mutant | outcome | seconds |", "|---|---|---:|"]
    for m in loom["mutants"]:
        lines.append(f"| `{m['file']}:{m['line']}`: {m['mutation']} | {OUT.get(m['outcome'], m['outcome'])} | {m['seconds']} |")
    lines.append("")
open("results/pool-mutants.md", "w").write("\n".join(lines))
print("results/pool-mutants.md written")
EOF
