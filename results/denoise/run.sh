#!/usr/bin/env bash
# The measurement of results/denoise/README.md (issue 32): raw and OIDN-denoised error of each method against a NoOpt
# reference at 1, 2, 4, ..., 128 frames, per scene and seed, as `raycoh converge --denoise oidn` rows. Resumable by
# scene and seed: a finished converge file is left as it is (converge reports it complete), an interrupted one is
# measured again. The references are NoOpt renders in the cache (results/cache/, not committed), made once by
# `raycoh reference` and passed as --reference FILE (with its -half1 image beside it for the noise estimate), so that
# a later revision of the code does not render them again.
# Usage: [RAYCOH=build/raycoh] [SEEDS="1 2 3"] [SCENES="..."] results/denoise/run.sh
set -euo pipefail
cd "$(dirname "$0")/../.."
raycoh=${RAYCOH:-build/raycoh}
seeds=${SEEDS:-"1 2 3"}
scenes=${SCENES:-"sibenik_lamps country_kitchen conference_lamps"}
# Reference frames per scene (conference_lamps: fewer, to fit the session's time; its ref_noise_share says so).
declare -A ref_frames=([sibenik_lamps]=1024 [country_kitchen]=1024 [conference_lamps]=512)
# sibenik_lamps has no hybrid groups (results/README.md, hybrid-reuse), so ours:hybrid=donor renders ours's rays
# there: it is left out of that scene.
generators() {
  if [[ $1 == sibenik_lamps ]]; then echo noopt,ours,contiguous,sadeghi,microjitter
  else echo noopt,ours,ours:hybrid=donor,contiguous,sadeghi,microjitter; fi
}
reference_of() {  # scene frames: the cached reference's image (rendered once when missing)
  local json
  json=$(grep -l "\"frames\": $2," results/cache/"$1"-*.json 2>/dev/null | xargs -r grep -l '"width": 480' | head -1 || true)
  if [[ -z $json ]]; then
    nice -n 5 "$raycoh" reference --scene ../shared/scenes/"$1" --res 480x270 --frames "$2" --tracer embree \
      --cache results/cache >&2
    json=$(grep -l "\"frames\": $2," results/cache/"$1"-*.json | xargs grep -l '"width": 480' | head -1)
  fi
  echo "${json%.json}.exr"
}
for seed in $seeds; do
  for s in $scenes; do
    ref=$(reference_of "$s" "${ref_frames[$s]}")
    start=$(date +%s)
    nice -n 5 "$raycoh" converge --scene ../shared/scenes/"$s" --generators "$(generators "$s")" --time 1000000s \
      --max-frames 128 --res 480x270 --tracer embree --gpu-model none --denoise oidn --seed "$seed" \
      --reference "$ref" --out results/denoise/converge_"$s"_seed"$seed".csv
    echo "run.sh: $s seed $seed: $(($(date +%s) - start)) s wall" >&2
  done
done
