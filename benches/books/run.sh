#!/usr/bin/env bash
# raypool against the books' own C++ (results/books.md, issue #57): fetch the v4 sources of
# *The Next Week* and *The Rest of Your Life*, build them with g++ -O2, and alternate them with
# raypool on the same settings, one thread: 200 × 200, depth 50.
#
#   next-week        the second book's final scene, 25 spp (next-week.patch sets the size, spp
#                    and depth) against raypool's next-week with the book's own box heights and
#                    sphere centres (book_numbers.cc, next_week.py) and its earthmap.jpg, --light-sampling bsdf
#   cornell-bsdf     the third book's Cornell box, 64 spp (cornell.patch), its mixture pdf replaced
#                    by the material's own (bsdf.patch), against --light-sampling bsdf
#   cornell-mixture  the third book as written (cornell.patch only) against --light-sampling mixture
#
# raypool runs --mode serial --threads 1 --sampler independent --edge-spots 0. Each pair runs the
# two programs back to back, the order swapped every pair; times are whole processes (scene
# build, image written). Prints a Markdown section: per scene, the median of the paired ratios
# book time ÷ raypool time (raypool's speed in multiples of the book's), the median times, and
# raypool's rays per second as it reports them.
#
# Usage: benches/books/run.sh [PAIRS=9] [SCENE...]    (from the repository root, after
#        cargo build --release)
# Environment:
#   BOOKS_REPO  where to fetch the books from (default GitHub; a local clone or mirror path works)
#   BOOKS_REF   the commit (default d3e5bf9, the v4.0.0-alpha.2 `dev` branch of 2024-03-25, the
#               newest v4 the project's mirror held; GitHub's `v4.0.0` tag is the release after it)
#   RAYPOOL     the raypool binary (default target/release/raypool)
#   WORK        a folder for the sources, builds and images (default a new temporary one, kept)
# Without network: fetch the repository elsewhere (git clone https://github.com/RayTracing/
# raytracing.github.io) and point BOOKS_REPO at the clone.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
pairs=${1:-9}
shift $(( $# > 0 ? 1 : 0 ))
scenes=("$@")
(( ${#scenes[@]} )) || scenes=(next-week cornell-bsdf cornell-mixture)
repo=${BOOKS_REPO:-https://github.com/RayTracing/raytracing.github.io}
ref=${BOOKS_REF:-d3e5bf95bd10414f840b184e4f57e52e4c54a493}
raypool=$(realpath "${RAYPOOL:-target/release/raypool}")
work=${WORK:-$(mktemp -d)}
mkdir -p "$work/bin"
say() { echo "$@" >&2; }

# The sources, patched and built: one binary per book setting.
src=$work/raytracing.github.io
if [[ ! -d $src/.git ]]; then
  say "fetching $repo at $ref into $src"
  git init -q "$src"
  git -C "$src" fetch -q --depth 1 "$repo" "$ref"
  git -C "$src" checkout -q FETCH_HEAD
fi
build() { # NAME BOOK-FOLDER PATCH...
  local name=$1 book=$2
  shift 2
  git -C "$src" checkout -q -- src
  for patch in "$@"; do git -C "$src" apply "$here/$patch"; done
  g++ -O2 -I "$src/src" "$src/src/$book/main.cc" -o "$work/bin/$name"
  git -C "$src" checkout -q -- src
}
build next-week TheNextWeek next-week.patch
build cornell-mixture TheRestOfYourLife cornell.patch
build cornell-bsdf TheRestOfYourLife cornell.patch bsdf.patch
g++ -O2 -I "$src/src/TheNextWeek" "$here/book_numbers.cc" -o "$work/bin/book-numbers"

# raypool's next-week with the book's numbers and, where Python's PIL can convert it, its earth.
"$work/bin/book-numbers" > "$work/numbers.txt"
earth=()
if python3 -c "from PIL import Image; Image.open('$src/images/earthmap.jpg').convert('RGB').save('$work/earthmap.png')" 2>/dev/null; then
  earth=(earthmap.png)
else
  say "no PIL: raypool's next-week keeps its own planet"
fi
"$raypool" scene next-week | python3 "$here/next_week.py" "$work/numbers.txt" "${earth[@]}" > "$work/next-week-book.toml"

flags=(--width 200 --depth 50 --mode serial --threads 1 --sampler independent --edge-spots 0)
raypool_args() {
  case $1 in
    next-week) echo --scene-file "$work/next-week-book.toml" --spp 25 --light-sampling bsdf ;;
    cornell-bsdf) echo --scene cornell --spp 64 --light-sampling bsdf ;;
    cornell-mixture) echo --scene cornell --spp 64 --light-sampling mixture ;;
    *) say "unknown scene $1 (next-week, cornell-bsdf, cornell-mixture)"; exit 2 ;;
  esac
}
book() { # SCENE: the book's time in seconds
  local t0=$EPOCHREALTIME
  RTW_IMAGES=$src/images "$work/bin/$1" > "$work/$1-book.ppm" 2> /dev/null
  awk -v a="$t0" -v b="$EPOCHREALTIME" 'BEGIN { printf "%.3f", b - a }'
}
ours() { # SCENE: raypool's time in seconds, then its Mrays/s
  local t0=$EPOCHREALTIME line
  # shellcheck disable=SC2046 # raypool_args prints words meant to be split
  line=$("$raypool" render "${flags[@]}" $(raypool_args "$1") --out "$work/$1-raypool.png" 2>&1)
  awk -v a="$t0" -v b="$EPOCHREALTIME" 'BEGIN { printf "%.3f ", b - a }'
  grep -o '[0-9.]* Mrays/s' <<<"$line" | cut -d' ' -f1
}
median() { sort -g | awk '{ v[NR] = $1 } END { printf "%.3f", (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2 }'; }

rows=()
for scene in "${scenes[@]}"; do
  raypool_args "$scene" > /dev/null
  ratios=() books=() oursec=() rates=()
  for k in $(seq "$pairs"); do
    if (( k % 2 )); then b=$(book "$scene"); read -r r m <<<"$(ours "$scene")"
    else read -r r m <<<"$(ours "$scene")"; b=$(book "$scene"); fi
    ratios+=("$(awk -v b="$b" -v r="$r" 'BEGIN { printf "%.4f", b / r }')")
    books+=("$b") oursec+=("$r") rates+=("$m")
    say "$scene pair $k: book $b s, raypool $r s ($m Mrays/s), ratio ${ratios[-1]}"
  done
  sorted=$(printf '%s\n' "${ratios[@]}" | sort -g | tr '\n' ' ')
  rows+=("| \`$scene\` | $pairs | $(printf '%s\n' "${books[@]}" | median) s | $(printf '%s\n' "${oursec[@]}" | median) s | $(printf '%s\n' "${rates[@]}" | median) | **$(printf '%s\n' "${ratios[@]}" | median)×** | ${sorted% } |")
done

commit=$(git -C "$here" rev-parse --short HEAD)
dirty=$(git -C "$here" status --porcelain --untracked-files=no | grep -q . && echo " (with uncommitted changes)" || true)
# A binary named by RAYPOOL may be another commit's: say which file ran, not this checkout's commit.
[[ -n ${RAYPOOL:-} ]] && { commit="binary $RAYPOOL (not necessarily this checkout's $commit)"; dirty=""; }
cat <<EOF
Command: \`benches/books/run.sh $pairs ${scenes[*]}\`; raypool $commit$dirty, the books at
$(git -C "$src" rev-parse --short HEAD) ($(git -C "$src" log -1 --format=%cs)), $(g++ --version | head -1), $(date -u +%Y-%m-%d);
machine: \`nproc\` $(nproc), $(lscpu | sed -n 's/^Model name: *//p' | head -1), load average $(cut -d' ' -f1-3 /proc/loadavg) at the end.

| scene | pairs | book (median) | raypool (median) | raypool Mrays/s | book ÷ raypool, median of pairs | every pair's ratio |
|---|---:|---:|---:|---:|---:|---|
$(printf '%s\n' "${rows[@]}")
EOF
