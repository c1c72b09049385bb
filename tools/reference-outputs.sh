#!/usr/bin/env bash
# Reference outputs for behaviour-preserving changes.
#
#   tools/reference-outputs.sh make BINARY OUTDIR
#       segments generated shapes and a few shared meshes with BINARY (default
#       band search, --exhaustive, --joints, a --tau list, armadillo at 256, an
#       elephant pose) into OUTDIR;
#   tools/reference-outputs.sh compare DIR_A DIR_B
#       byte-compares labels.nrrd, skeleton.ply, cuts.ply, segmentation.seg,
#       hierarchy.json and levels/*/* of every run; exit 1 when any differs.
#
# Make one directory with main's build and one with the change's, then
# compare them. Shared meshes are read from SKELSEG_SHARED_DATA (default
# ../shared/data next to the repository); runs whose mesh is absent are skipped.
set -euo pipefail

usage() {
    echo "usage: $0 make BINARY OUTDIR | compare DIR_A DIR_B" >&2
    exit 2
}

make_outputs() {
    local bin=$1 out=$2
    local data=${SKELSEG_SHARED_DATA:-$(cd "$(dirname "$0")/.." && pwd)/../shared/data}
    mkdir -p "$out/in"
    local run=(-q --no-preview --force)
    for s in disc-limbs y-arms t-body slab box-tubes torus-limb capsule cylinder sphere box torus; do
        "$bin" generate "$s" -o "$out/in/$s.nrrd" --size 80 >/dev/null
        "$bin" segment "$out/in/$s.nrrd" -o "$out/$s" "${run[@]}"
    done
    for pose in 0 1 2; do
        "$bin" generate figure -o "$out/in/figure$pose.nrrd" --size 112 --pose "$pose" >/dev/null
        "$bin" segment "$out/in/figure$pose.nrrd" -o "$out/figure$pose" "${run[@]}"
    done
    "$bin" generate figure -o "$out/in/noisy.nrrd" --size 96 --pose 1 --noise 0.02 --seed 11 >/dev/null
    "$bin" segment "$out/in/noisy.nrrd" -o "$out/noisy" "${run[@]}"
    "$bin" segment "$out/in/figure1.nrrd" -o "$out/figure1-levels" "${run[@]}" --tau 1%,3%,9%
    mesh() {  # NAME FILE ARGS...: one shared mesh, skipped when absent
        local name=$1 file=$data/$2
        shift 2
        if [ -f "$file" ]; then
            "$bin" segment "$file" -o "$out/$name" "${run[@]}" "$@"
        else
            echo "skipped $name: $file absent" >&2
        fi
    }
    mesh hand shapes/hand.off --resolution 128 --tau 1%
    mesh psb1 psb/off/1.off --resolution 128
    mesh samba45 poses/samba_0045.obj --resolution 128
    mesh armadillo256 shapes/armadillo.obj --resolution 256
    mesh hand-exh shapes/hand.off --resolution 128 --exhaustive
    mesh psb1-joints psb/off/1.off --resolution 128 --joints
    mesh eleph1 poses/elephantgallop_1.obj --resolution 192
}

compare_outputs() {
    local a=$1 b=$2 bad=0 n=0 f
    while IFS= read -r f; do
        n=$((n + 1))
        cmp -s "$a/$f" "$b/$f" || { echo "DIFFER: $f"; bad=1; }
    done < <(cd "$a" && find . -path ./in -prune -o -type f \( -name labels.nrrd -o -name skeleton.ply \
        -o -name cuts.ply -o -name segmentation.seg -o -name hierarchy.json \) -print | sort)
    echo "compared $n files; $([ $bad = 0 ] && echo identical || echo DIFFERENT)"
    return $bad
}

for argument in "$@"; do
    case $argument in
        -h | --help)
            echo "usage: $0 make BINARY OUTDIR | compare DIR_A DIR_B"
            echo "  make: segment the reference shapes with BINARY into OUTDIR"
            echo "  compare: byte-compare two such folders; exit 1 when any output differs"
            exit 0
            ;;
        -*)
            echo "$0: unknown option '$argument'" >&2
            exit 2
            ;;
    esac
done
[ $# -eq 3 ] || usage
case $1 in
    make) make_outputs "$2" "$3" ;;
    compare) compare_outputs "$2" "$3" ;;
    *) usage ;;
esac
