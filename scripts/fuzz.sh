#!/usr/bin/env bash
# Fuzzes every reader with libFuzzer: builds tests/fuzz/ with clang in build-fuzz/ (-DUVR_FUZZ=ON: libFuzzer,
# AddressSanitizer, LeakSanitizer, UndefinedBehaviorSanitizer) and runs each target in turn, one at a time.
#
#   bash scripts/fuzz.sh [SECONDS_PER_TARGET] [TARGET...]     (default 60 seconds; targets: vtk_legacy vtu ... camera)
#
# Seeds: the small hand-made files of tests/fuzz/corpus/<target>/ and seeds made here from data/ (small files
# whole, prefixes of large ones, small valid sub-volumes and sub-grids cut out of the large ones); the data are
# never copied into the repository. The corpus grows in build-fuzz/corpus/<target>/ from run to run. Findings (crash,
# sanitizer report, leak, uncaught exception other than uvr::InputError, timeout, out-of-memory) are saved in
# build-fuzz/findings/<target>/ and their logs in build-fuzz/logs/; the script prints executions and findings per
# target, and exits 1 when any target has a finding. docs/robustness.md explains how to reproduce and triage one.
# Environment: UVR_JOBS (build parallelism, default: the number of cores), UVR_DATA_DIR (the data sets, default
# data/), UVR_FUZZ_ARGS (extra libFuzzer flags), UVR_FUZZ_SKIP_BUILD=1 (run the targets already built).
set -euo pipefail
cd "$(dirname "$0")/.."
root=$PWD
seconds="${1:-60}"
shift || true
all=(vtk_legacy vtu vti tetgen off plot3d nrrd mha slc raw_volume exodus transfer_function camera)
targets=("$@")
[ ${#targets[@]} -gt 0 ] || targets=("${all[@]}")
data="${UVR_DATA_DIR:-$root/data}"
out="$root/build-fuzz"

# clang 14 and its libFuzzer/sanitizer runtimes (Debian 12) come with the rest (install-deps.sh).
bash scripts/install-deps.sh

if [ "${UVR_FUZZ_SKIP_BUILD:-0}" != 1 ]; then
  cmake -S . -B "$out" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_C_COMPILER=clang \
    -DCMAKE_CXX_COMPILER=clang++ -DUVR_FUZZ=ON -DBUILD_TESTING=OFF >/dev/null
  cmake --build "$out" -j "${UVR_JOBS:-$(nproc)}" --target fuzz_targets
fi

# ---- seeds made from the data sets (build-fuzz/seeds/<target>/, remade every run) ----
seeds="$out/seeds"
rm -rf "$seeds"
for t in "${all[@]}"; do mkdir -p "$seeds/$t"; done
be32() { printf "\\x$(printf %02x $(($1 >> 24 & 255)))\\x$(printf %02x $(($1 >> 16 & 255)))\\x$(printf %02x $(($1 >> 8 & 255)))\\x$(printf %02x $(($1 & 255)))"; }
le32() { printf "\\x$(printf %02x $(($1 & 255)))\\x$(printf %02x $(($1 >> 8 & 255)))\\x$(printf %02x $(($1 >> 16 & 255)))\\x$(printf %02x $(($1 >> 24 & 255)))"; }
# bytes FILE OFFSET COUNT: COUNT bytes of FILE from OFFSET.
bytes() { dd if="$1" iflag=skip_bytes,count_bytes skip="$2" count="$3" bs=65536 status=none; }
v="$data/vtk-data"
if [ -d "$v" ]; then
  # VTK legacy: the small meshes whole, the large files' first 4 and 16 KiB (valid headers, then truncated data).
  cp "$v/tetraMesh.vtk" "$v/uGridEx.vtk" "$seeds/vtk_legacy/"
  for f in post a_grid hexa ironProt; do
    bytes "$v/$f.vtk" 0 4096 >"$seeds/vtk_legacy/$f.4k.vtk"
    bytes "$v/$f.vtk" 0 16384 >"$seeds/vtk_legacy/$f.16k.vtk"
  done
  # VTK XML: Tetrahedron.vtu whole (appended raw, UInt64 headers); the zlib-compressed .vti files' first 16 KiB.
  cp "$v/Tetrahedron.vtu" "$seeds/vtu/"
  bytes "$v/hydrogen.vti" 0 16384 >"$seeds/vti/hydrogen.16k.vti"
  bytes "$v/vase.vti" 0 16384 >"$seeds/vti/vase.16k.vti"
  # TetGen and OFF: tetraMesh.vtk's 55 points and 160 tetrahedra rewritten in those formats.
  awk '/^POINTS/{p=$2; mode="p"; next} /^CELLS/{c=$2; mode="c"; next} /^CELL_TYPES/{mode=""}
       mode=="p" && NF==3 {pts[np++]=$0} mode=="c" && NF==5 {cells[nc++]=$2" "$3" "$4" "$5}
       END {printf "%d 3 0 0\n", np; for (i=0;i<np;i++) print i, pts[i];
            printf "UVRSPLIT%d 4 0\n", nc; for (i=0;i<nc;i++) print i, cells[i]}' \
      "$v/tetraMesh.vtk" >"$seeds/tetgen/tetraMesh.txt"
  awk '/^POINTS/{mode="p"; next} /^CELLS/{mode="c"; next} /^CELL_TYPES/{mode=""}
       mode=="p" && NF==3 {pts[np++]=$0} mode=="c" && NF==5 {cells[nc++]=$0}
       END {printf "OFF\n%d %d 0\n", np, nc; for (i=0;i<np;i++) print pts[i]; for (i=0;i<nc;i++) print cells[i]}' \
      "$v/tetraMesh.vtk" >"$seeds/off/tetraMesh.off"
  # PLOT3D: 40x2x2 sub-grids of Blunt Fin (40x32x32) and its Q values, and 38x2x2 of the LOX post (38x76x38), whose
  # grid has iblank. The whole-file layout is header, x[], y[], z[] (, iblank[]), i fastest, so the sub-grid of an
  # array is two runs of 2*nx values, one per k.
  subgrid() {  # FILE HEADER_BYTES ARRAYS NX NY NZ: the (NX, 2, 2) corner of each of ARRAYS arrays of NX*NY*NZ values
    local a k
    for a in $(seq 0 $(($3 - 1))); do
      for k in 0 1; do bytes "$1" $(($2 + (a * $4 * $5 * $6 + k * $4 * $5) * 4)) $((2 * $4 * 4)); done
    done
  }
  {
    be32 40; be32 2; be32 2; subgrid "$v/bluntfinxyz.bin" 12 3 40 32 32
    printf UVRSPLIT
    be32 40; be32 2; be32 2; bytes "$v/bluntfinq.bin" 12 16; subgrid "$v/bluntfinq.bin" 28 5 40 32 32
  } >"$seeds/plot3d/bluntfin_40x2x2.bin"
  {
    be32 38; be32 2; be32 2; subgrid "$v/postxyz.bin" 12 4 38 76 38
    printf UVRSPLIT
    be32 38; be32 2; be32 2; bytes "$v/postq.bin" 12 16; subgrid "$v/postq.bin" 28 5 38 76 38
  } >"$seeds/plot3d/post_38x2x2_iblank.bin"
  bytes "$v/bluntfinxyz.bin" 0 4096 >"$seeds/plot3d/bluntfin.4k.xyz"
  # NRRD: quarter.nhdr with its first slice attached (64x64x1 int16); MetaImage: HeadMRVolume's first slice as .mha.
  { sed -e 's/^sizes: .*/sizes: 64 64 1/' -e '/^data file/d' "$v/headsq/quarter.nhdr"; echo; cat "$v/headsq/quarter.1"; } \
    >"$seeds/nrrd/quarter_slice1.nrrd"
  { sed -e 's/^DimSize = .*/DimSize = 48 62 1/' -e 's/^ElementDataFile = .*/ElementDataFile = LOCAL/' \
      "$v/HeadMRVolume.mhd"; bytes "$v/HeadMRVolume.raw" 0 $((48 * 62)); } >"$seeds/mha/HeadMR_slice0.mha"
  # SLC: neghip.slc's first 36 KiB (header, 100x100 icon, the first slices); and its header with no icon and 2 slices, then its RLE slices.
  bytes "$v/neghip.slc" 0 36000 >"$seeds/slc/neghip.36k.slc"
  x=$(bytes "$v/neghip.slc" 0 200 | grep -abo X | awk -F: 'NR == 1 {print $1}')  # awk reads all: no SIGPIPE
  { printf '11111\n66 66 2 8\n1.000000 1.000000 1.000000\n1 6 0 1\n0 0 X'; bytes "$v/neghip.slc" $((x + 1 + 30000)) 6000; } \
    >"$seeds/slc/neghip_2slices.slc"
  # Raw volumes: a 64x64x1 slice of neghip and a 48x62x1 slice of HeadMRVolume (uint8).
  { printf '\x00'; le32 64; le32 64; le32 1; bytes "$data/open-scivis/neghip_64x64x64_uint8.raw" 0 4096; } \
    >"$seeds/raw_volume/neghip_slice.bin"
  { printf '\x00'; le32 48; le32 62; le32 1; bytes "$v/HeadMRVolume.raw" 0 $((48 * 62)); } >"$seeds/raw_volume/headmr_slice.bin"
else
  echo "fuzz: no data at $data; fuzzing from tests/fuzz/corpus only"
fi

# ---- fuzzing, one target at a time ----
total_findings=0
summary=()
for t in "${targets[@]}"; do
  bin="$out/tests/fuzz/fuzz_$t"
  [ -x "$bin" ] || { echo "fuzz: no target fuzz_$t (known: ${all[*]})"; exit 2; }
  corpus="$out/corpus/$t" findings="$out/findings/$t" log="$out/logs/$t.log"
  mkdir -p "$corpus" "$findings" "$out/logs"
  before=$(find "$findings" -type f | wc -l)
  dict=()
  [ -f tests/fuzz/dict/$t.dict ] && dict=(-dict=tests/fuzz/dict/$t.dict)
  echo "fuzz: $t for ${seconds}s"
  # -fork=1 runs the fuzzing in a child process that is restarted after a finding, so one finding does not end the
  # target's time; -ignore_* keep going after each kind of finding (each one is still saved under findings/).
  set +e
  UVR_FUZZ_TMP=/dev/shm "$bin" -fork=1 -ignore_crashes=1 -ignore_timeouts=1 -ignore_ooms=1 \
    -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 -malloc_limit_mb=1024 -max_len=65536 \
    -artifact_prefix="$findings/" "${dict[@]}" ${UVR_FUZZ_ARGS:-} \
    "$corpus" tests/fuzz/corpus/$t "$seeds/$t" >"$log" 2>&1
  rc=$?
  set -e
  execs=$(grep -oE '^#[0-9]+' "$log" | tail -1 | tr -d '#')
  crashes=$(grep -oE 'oom/timeout/crash: [0-9]+/[0-9]+/[0-9]+' "$log" | tail -1 | cut -d' ' -f2)
  after=$(find "$findings" -type f | wc -l)
  new=$((after - before))
  total_findings=$((total_findings + new))
  line=$(printf '%-18s %12s executions  corpus %5s files  oom/timeout/crash %-9s  new findings %d (rc %d)' \
    "$t" "${execs:-?}" "$(find "$corpus" -type f | wc -l)" "${crashes:-0/0/0}" "$new" "$rc")
  echo "$line"
  summary+=("$line")
done
echo
echo "fuzz: ${seconds}s per target"
printf '%s\n' "${summary[@]}"
if [ "$total_findings" -gt 0 ]; then
  echo "fuzz: $total_findings new finding(s), saved under build-fuzz/findings/ (logs in build-fuzz/logs/)"
  exit 1
fi
echo "fuzz: no findings"
