#!/usr/bin/env bash
# Runs every plot script in scripts/ on small CSV files and PNG images written here, checks that each figure
# (and the markdown table) is written, and that bad input gives a one-line error and exit code 2.
# Usage: tests/scripts_test.sh <scripts dir> <work dir>. Needs /usr/bin/python3 with matplotlib (scripts/setup).
set -euo pipefail
scripts=$(cd "$1" && pwd)
work=$2
rm -rf "$work" && mkdir -p "$work" && cd "$work"
export MPLBACKEND=Agg

/usr/bin/python3 -c "import matplotlib" || { echo "scripts_test: /usr/bin/python3 has no matplotlib (run scripts/setup)"; exit 1; }

# `raycoh table` / `raycoh sweep` rows (the columns the scripts read, plus a few others).
cat > table.csv <<'CSV'
scene,pass,method,generator,generator_params,encoder,tracer,tracer_params,tile_w,tile_h,k,order,preset,mode,frame,rays,trace_ms,e2e_ms,mray_s
cornell,primary,primary,primary,"order=tile,tile=8x8",,cpu,,8,8,,tile,,,0,1000,0.5,0.5,2
cornell,secondary,noopt,noopt,"order=tile,tile=8x8",none,cpu,,8,8,,tile,,,0,900,1.0,1.1,0.9
cornell,secondary,ours,ours,"tile=8x8,k=8,order=tile,seed=0",none,cpu,,8,8,8,tile,,,0,900,0.8,0.9,1.125
cornell,secondary,noopt+origin,noopt,"order=tile,tile=8x8",origin,cpu,,8,8,,tile,,,0,900,0.9,1.3,1.0
voxels,secondary,noopt,noopt,"order=tile,tile=8x8",none,cpu,,8,8,,tile,,,0,800,2.0,2.1,0.4
voxels,secondary,ours,ours,"tile=8x8,k=8,order=tile,seed=0",none,cpu,,8,8,8,tile,,,0,800,1.5,1.6,0.53
voxels,secondary,noopt+origin,noopt,"order=tile,tile=8x8",origin,cpu,,8,8,,tile,,,0,800,1.9,2.5,0.42
CSV
cat > sweep.csv <<'CSV'
scene,pass,method,generator,generator_params,encoder,tracer,tracer_params,tile_w,tile_h,k,order,preset,mode,frame,rays,trace_ms
sibenik,secondary,noopt,noopt,"order=tile,tile=8x8",none,cpu,,8,8,,tile,,,0,1000,2.0
sibenik,secondary,"ours:tile=8x8,k=8",ours,"tile=8x8,k=8,order=tile,seed=0",none,cpu,,8,8,8,tile,,,0,1000,1.6
sibenik,secondary,"ours:tile=8x8,k=16",ours,"tile=8x8,k=16,order=tile,seed=0",none,cpu,,8,8,16,tile,,,0,1000,1.4
sibenik,secondary,"ours:tile=16x8,k=8",ours,"tile=16x8,k=8,order=tile,seed=0",none,cpu,,16,8,8,tile,,,0,1000,1.7
sibenik,secondary,"ours:tile=16x8,k=16",ours,"tile=16x8,k=16,order=tile,seed=0",none,cpu,,16,8,16,tile,,,0,1000,1.5
CSV
cat > converge.csv <<'CSV'
scene,method,frame,wall_s,trace_s,rel_mse,mse,rmse,psnr,ssim,preset,mode,gpu_preset
cornell,noopt,1,0.1,0.05,1.0,0.1,0.31,15,0.3,,,
cornell,noopt,2,0.2,0.1,0.5,0.05,0.22,18,0.4,,,
cornell,noopt,3,0.3,0.15,0.33,0.033,0.18,19.8,0.5,,,
cornell,ours,1,0.08,0.03,1.1,0.11,0.33,14.8,0.3,,,
cornell,ours,2,0.16,0.06,0.56,0.056,0.24,17.7,0.4,,,
cornell,ours,3,0.24,0.09,0.37,0.037,0.19,19.5,0.5,,,
CSV
cat > converge-summary.csv <<'CSV'
scene,method,baseline,metric,clock,horizon_s,error,baseline_error,equal_time_error_ratio,target_error,time_s,baseline_time_s,equal_error_speedup
cornell,ours,noopt,rel_mse,wall,0.24,0.37,0.41,0.9,0.37,0.24,0.27,1.12
CSV
# The same with the modeled GPU clock (converge --gpu-model).
cat > converge_gpu.csv <<'CSV'
scene,method,frame,wall_s,trace_s,rel_mse,mse,rmse,psnr,ssim,gpu_model,modeled_gpu_s,preset,mode,gpu_preset
cornell,noopt,1,0.1,0.05,1.0,0.1,0.31,15,0.3,simt[preset=rtx3060],0.002,,,rtx3060
cornell,noopt,2,0.2,0.1,0.5,0.05,0.22,18,0.4,simt[preset=rtx3060],0.004,,,rtx3060
cornell,ours,1,0.08,0.03,1.1,0.11,0.33,14.8,0.3,simt[preset=rtx3060],0.001,,,rtx3060
cornell,ours,2,0.16,0.06,0.56,0.056,0.24,17.7,0.4,simt[preset=rtx3060],0.002,,,rtx3060
CSV
cat > quality.csv <<'CSV'
scene,method,frames,ref_frames,psnr,psnr_std,ssim,rel_mse,rmse,bias2,preset,mode
cornell,noopt,32,512,25.1,0.15,0.70,0.05,0.06,0.0002,,
cornell,ours,32,512,25.0,0.08,0.70,0.049,0.06,0.00024,,
sibenik,noopt,32,512,19.6,0.2,0.6,0.1,0.01,0.000001,,
sibenik,ours,32,512,19.5,0.1,0.6,0.1,0.01,0.000001,,
CSV
# `raycoh validate` rows (two Table 1 rows, a Table 3 row per tile and K = 8, 16), and a simt table row.
{
  echo "table,row,paper_row,tile,k,paper_mray_s,paper_ratio,modeled_mray_s,modeled_ratio,ratio_error,modeled_limiter,preset,tracer_params,order"
  m='"simt[preset=rtx3060,l2_bpc=1327]",tile'
  echo "table1,noopt,NoOpt,,0,154.7,1,300,1,0,l1,rtx3060,$m"
  echo "table1,\"ours:tile=8x8,k=8\",Ours,8x8,8,278.5,1.8,420,1.4,-0.22,l1,rtx3060,$m"
  for t in 8x8 32x8; do for k in 8 16 32 64; do
    echo "table3,\"ours:tile=$t,k=$k\",($t) K=$k,$t,$k,250,1.6,400,$((k > 16 ? 2 : 1)).2,-0.$((k / 8)),l1,rtx3060,$m"
  done; done
} > validate.csv
sed 's/l2_bpc=1327/l2_bpc=600/' validate.csv > validate_l2.csv
sed -e 's/,mray_s$/,mray_s,modeled_ms,modeled_e2e_ms/' -e '2,$s/$/,,/' table.csv > table_simt.csv
echo "cornell,secondary,noopt,noopt,\"order=tile,tile=8x8\",none,simt,,8,8,,tile,rtx3060,,0,900,50.0,50.0,0.018,0.003,0.004" >> table_simt.csv
echo "cornell,secondary,ours,ours,\"tile=8x8,k=8,order=tile,seed=0\",none,simt,,8,8,8,tile,rtx3060,,0,900,60.0,60.0,0.015,0.002,0.003" >> table_simt.csv
cat > model.csv <<'CSV'
scene,method,width,height,rays,modeled_ms,modeled_e2e_ms
sibenik,noopt,64,32,2000,2.0,2.5
sibenik,ours,64,32,2000,1.0,1.5
sibenik,primary,64,32,2048,0.5,
CSV
/usr/bin/python3 - <<'PY'
import numpy as np
import matplotlib.image as mpimg
y, x = np.mgrid[0:48, 0:64]
for i, name in enumerate(["reference", "noopt", "ours"]):
    img = np.stack([x / 63.0, y / 47.0, np.full(x.shape, i / 2.0)], axis=-1)
    mpimg.imsave(f"{name}.png", img)
PY

check() {  # check <file>: written and not empty
  [[ -s $1 ]] || { echo "scripts_test: $1 was not written"; exit 1; }
}
expect_error() {  # expect_error <text> <command...>: exit code 2 and the text in the one-line error
  local text=$1; shift
  local out rc=0
  out=$("$@" 2>&1) || rc=$?
  [[ $rc -eq 2 && $out == *"$text"* ]] || { echo "scripts_test: '$*' gave rc $rc, output: $out"; exit 1; }
}

"$scripts/plot_table.py" table.csv --out fig/table.png --primary && check fig/table.png
"$scripts/plot_table.py" table.csv --out fig/table_e2e.pdf --speed e2e --tracer cpu && check fig/table_e2e.pdf
"$scripts/plot_sweep.py" sweep.csv --out fig/sweep.png && check fig/sweep.png
"$scripts/plot_sweep.py" sweep.csv --out fig/sweep_mray.svg --value mray && check fig/sweep_mray.svg
"$scripts/plot_converge.py" converge.csv --out fig/converge.png && check fig/converge.png
"$scripts/plot_converge.py" converge.csv --out fig/converge_psnr.png --metric psnr --clock trace_s && check fig/converge_psnr.png
"$scripts/plot_converge.py" converge_gpu.csv --out fig/converge_gpu.png && check fig/converge_gpu.png
"$scripts/plot_converge.py" converge_gpu.csv --out fig/converge_3.png --clock wall_s,trace_s,modeled_gpu_s && check fig/converge_3.png
sed 's/^cornell,/voxels,/' converge_gpu.csv > converge_gpu2.csv
"$scripts/plot_converge.py" converge_gpu.csv converge_gpu2.csv --out fig/converge_2.png && check fig/converge_2.png
# The device clock (converge --device cuda and cuda:pipeline=fused): one curve per method and form, the clock's
# kind in the axis; measured and simulated rows in one plot are refused.
{ echo "scene,method,frame,wall_s,trace_s,rel_mse,mse,rmse,psnr,ssim,preset,mode,gpu_preset,render_device,gpu_clock,gpu_s"
  for d in cuda cuda:pipeline=fused; do
    echo "cornell,noopt,1,0.1,0,1.0,0.1,0.31,15,0.3,,,,$d,measured,0.002"
    echo "cornell,noopt,2,0.2,0,0.5,0.05,0.22,18,0.4,,,,$d,measured,0.004"
    echo "cornell,ours,1,0.1,0,0.9,0.1,0.31,15,0.3,,,,$d,measured,0.0015"
  done; } > converge_dev.csv
"$scripts/plot_converge.py" converge_dev.csv --out fig/converge_dev.png --clock gpu_s && check fig/converge_dev.png
sed '3s/measured/simulated/' converge_dev.csv > converge_mixed.csv
expect_error "one of measured or simulated per plot" "$scripts/plot_converge.py" converge_mixed.csv --out fig/x.png --clock gpu_s
"$scripts/plot_quality.py" quality.csv --out fig/quality.png --markdown fig/quality.md && check fig/quality.png
check fig/quality.md
grep -q "| ours | 25.00 | 19.50 |" fig/quality.md || { echo "scripts_test: unexpected table:"; cat fig/quality.md; exit 1; }
"$scripts/plot_validate.py" validate.csv --out fig/validate.png && check fig/validate.png
"$scripts/validate_summary.py" validate.csv validate_l2.csv --labels base,l2 --out fig/validate.md && check fig/validate.md
grep -q "| l2 | l2_bpc=600 | tile | 300.0 | l1 | 1.40 | 2/9 | 36% | 80% | +0.0% |" fig/validate.md ||
  { echo "scripts_test: unexpected validate summary:"; cat fig/validate.md; exit 1; }
expect_error "2 names for 1 CSV" "$scripts/validate_summary.py" validate.csv --labels a,b
"$scripts/plot_table.py" table_simt.csv --out fig/table_simt.png --speed e2e && check fig/table_simt.png
"$scripts/model_summary.py" model.csv --out fig/model.md && check fig/model.md
grep -q "| sibenik | 64x32 | 1 | 2.00x (1.67x e2e) | 4.10x |" fig/model.md ||
  { echo "scripts_test: unexpected model summary:"; cat fig/model.md; exit 1; }
"$scripts/montage.py" reference.png noopt.png ours.png --out fig/montage.png && check fig/montage.png
"$scripts/montage.py" reference.png noopt.png ours.png --crop 8,4,16,12 --labels ref,noopt,ours --out fig/crops.png
check fig/crops.png

expect_error "no such CSV file" "$scripts/plot_table.py" missing.csv --out fig/x.png
expect_error "missing column" "$scripts/plot_converge.py" quality.csv --out fig/x.png
# A CSV written before the typed columns (tile_w, tile_h, k, preset, mode) is refused, naming the file and them.
/usr/bin/python3 -c "
import csv
rows = list(csv.reader(open('sweep.csv')))
csv.writer(open('sweep_old.csv', 'w'), lineterminator='\\n').writerows([r[:8] + r[14:] for r in rows])"
expect_error "sweep_old.csv: missing column(s) tile_w, tile_h, k, preset, mode" "$scripts/plot_sweep.py" sweep_old.csv --out fig/x.png
expect_error "missing column" "$scripts/plot_converge.py" converge.csv --out fig/x.png --clock modeled_gpu_s
expect_error "expected one of" "$scripts/plot_converge.py" converge.csv --out fig/x.png --clock gpu
grep -v ",noopt," table.csv > no_baseline.csv
expect_error "no noopt rows" "$scripts/plot_table.py" no_baseline.csv --out fig/x.png
expect_error "not inside" "$scripts/montage.py" reference.png --crop 60,40,16,16 --out fig/x.png
expect_error "no such image file" "$scripts/montage.py" nothing.png --out fig/x.png
expect_error "nothing to do" "$scripts/plot_quality.py" quality.csv
expect_error "missing column" "$scripts/plot_validate.py" table.csv --out fig/x.png
grep "^table1" validate.csv > table1_only.csv && sed -i "1i $(head -1 validate.csv)" table1_only.csv
expect_error "needs table1 and table3" "$scripts/plot_validate.py" table1_only.csv --out fig/x.png
# converge_seeds.py: mean and standard error over seeds' summaries.
printf 'scene,method,baseline,metric,clock,equal_time_error_ratio,equal_error_speedup\ns,ours,noopt,rel_mse,modeled_gpu,0.9,1.1\n' > seed1-summary.csv
printf 'scene,method,baseline,metric,clock,equal_time_error_ratio,equal_error_speedup\ns,ours,noopt,rel_mse,modeled_gpu,1.0,1.0\n' > seed2-summary.csv
"$scripts/converge_seeds.py" seed1-summary.csv seed2-summary.csv --md seeds.md > /dev/null
grep -q "| s | ours vs noopt | modeled_gpu (MODELED) | 2 | 0.950 ± 0.050 | 1/2 | 1.050 ± 0.050 |" seeds.md ||
  { echo "scripts_test: converge_seeds.py table wrong: $(cat seeds.md)"; exit 1; }
expect_error "missing column" "$scripts/converge_seeds.py" table.csv
# denoise_table.py: relMSE ratios to noopt, raw and denoised, over seeds (issue 32).
for seed in 1 2; do
  printf 'scene,method,seed,frame,rel_mse,denoised_rel_mse,rel_mse_corr,denoised_rel_mse_corr\n' > dn$seed.csv
  printf 's,noopt,%s,1,1.0,0.1,1.0,0.1\ns,ours,%s,1,1.1,0.2,1.1,0.2\ns,ours,%s,2,0.6,,0.6,\n' $seed $seed $seed >> dn$seed.csv
done
sed -i 's/^s,ours,2,1,1.1,0.2,1.1,0.2$/s,ours,2,1,0.9,0.3,0.9,0.3/' dn2.csv
"$scripts/denoise_table.py" dn1.csv dn2.csv --frames 1 > dn.md
grep -q "| ours | 1 | 0.99 (0.90–1.10) | 2.45 (2.00–3.00) | 2.46 (1.82–3.33) | widens (every seed) | +0 / +0.15 |" dn.md &&
  grep -q "| noopt denoised / raw | 1 | | | 0.10 (0.10–0.10) | denoiser lowers the error | noopt 1 / 0.1 |" dn.md ||
  { echo "scripts_test: denoise_table.py table wrong: $(cat dn.md)"; exit 1; }
expect_error "no column seed (a converge CSV of --denoise oidn is needed)" "$scripts/denoise_table.py" converge.csv
# bounce_speed.py: each bounce's device trace speed and its ratio to noopt, said faster only outside the interval.
{ echo "scene,method,frame,render_device,gpu_clock,gpu_first_trace_ms,gpu_second_trace_ms,first_wave_rays,second_wave_rays"
  for f in 1 2 3 4 5 6; do
    echo "s,noopt,$f,cuda,measured,1.0$f,2.0$f,1000,900"; echo "s,ours,$f,cuda,measured,0.5$f,2.0$((7 - f)),1000,900"
  done; echo "s,ours,1,cpu,,,,,"; } > bounces.csv
"$scripts/bounce_speed.py" bounces.csv > bounces.md
grep -q "^### s, cuda: each bounce's trace speed, MEASURED" bounces.md &&
  grep -qF "| ours | 6 | 1.869 [1.786, 1.961] | 0.4423 [0.4369, 0.4478] | 1.935× [1.864, 2.019] faster | 1.000× [0.988, 1.015] indistinguishable |" bounces.md ||
  { echo "scripts_test: bounce_speed.py table wrong: $(cat bounces.md)"; exit 1; }
expect_error "no column render_device (converge rows of the device path tracer" "$scripts/bounce_speed.py" converge.csv
# scripts/paper-protocol refuses bad input before it renders or creates anything.
expect_error "usage: scripts/paper-protocol" "$scripts/paper-protocol" build 480x270
expect_error "no scene file ../shared/scenes/no_such_scene" "$scripts/paper-protocol" build 480x270 "$work/refs" no_such_scene
[[ ! -e $work/refs ]] || { echo "scripts_test: paper-protocol created $work/refs on bad input"; exit 1; }
# model_vs_sim.py: one SIMULATED (cuda) and one MODELED (simt) row per cell of a model-vs-sim run.
mkdir -p mvs/runs
cat > mvs/runs/cornell_32x24_sms2_gen.csv <<'CSV'
scene,method,generator_params,tracer,rays,trace_ms,modeled_ms,modeled_limiter,simt_efficiency,l1_misses_per_ray,git_revision
cornell,noopt,order=tile,cuda,2304,0.1,,,,,abc
cornell,noopt,order=tile,simt,2304,,0.05,issue,0.5,1.0,abc
cornell,ours:order=group,order=group,cuda,2304,0.08,,,,,abc
cornell,ours:order=group,order=group,simt,2304,,0.05,l1,0.6,0.8,abc
CSV
"$scripts/model_vs_sim.py" mvs fig/model_vs_sim.png > /dev/null
[[ -s fig/model_vs_sim.png ]] || { echo "scripts_test: model_vs_sim.py wrote no figure"; exit 1; }
grep -q "| cornell | 32x24 | ours:order=group | 2304 | 1.00 | 90,560 | 56,600 | -38% | l1 | 1.25 | 1.00 | -20% |" \
  mvs/table.md || { echo "scripts_test: model_vs_sim.py table wrong: $(cat mvs/table.md)"; exit 1; }
expect_error "no runs/" "$scripts/model_vs_sim.py" table.csv fig/x.png
# scripts/gpu-check's summaries of a run whose bench or counters are missing (a GPGPU-Sim dry run, a failed step).
# stage_bounds.py without raycoh_bench_stages' CSV: the stages and the verdict, labelled simulated, no bounds.
{ echo "scene,pass,method,generator_params,encoder_params,tracer,pipeline,frame,rays,gen_ms,modeled_gen_bytes,trace_ms,gpu_e2e_ms,device"
  for p in device fused; do
    echo "s,secondary,noopt,,,cuda,$p,0,100,1.0,2000000,4.0,6.0,simulated: GPGPU-Sim"
    echo "s,secondary,ours,,,cuda,$p,0,100,1.5,2000000,2.0,4.0,simulated: GPGPU-Sim"
  done; } > stages-s.csv
/usr/bin/python3 "$scripts/stage_bounds.py" no-bounds.csv stages-s.csv > stages.md
grep -q "^## Device stages beside their bounds (SIMULATED (GPGPU-Sim), not hardware)" stages.md &&
  grep -q "^No stage bounds: no-bounds.csv is missing" stages.md && grep -qF "| s | ours | gen | 1.5000 | 2.0 |  | |" stages.md &&
  grep -qF "| s | ours | 2.000 | 4.0000 | 1.500 | 4.0000 | 1.500 | 0.750 |" stages.md ||
  { echo "scripts_test: stage_bounds.py without bounds wrong: $(cat stages.md)"; exit 1; }
# hw_counters_check.py on counters=hw rows that read no counters: simulated says so and passes, a GPU's fails.
{ echo "scene,method,tracer,tracer_params,rays,run_under,hw_l1_hit_pct,device"
  echo "s,noopt,cuda,\"counters=hw,bvh=bvh2\",100,,,simulated: GPGPU-Sim"; } > hw-sim.csv
sed 's/simulated: GPGPU-Sim/NVIDIA H200/' hw-sim.csv > hw-gpu.csv
/usr/bin/python3 "$scripts/hw_counters_check.py" hw-sim.csv none.log | grep -q "simulated device (GPGPU-Sim): no hardware" ||
  { echo "scripts_test: hw_counters_check.py on simulated rows did not pass with its line"; exit 1; }
out=$(/usr/bin/python3 "$scripts/hw_counters_check.py" hw-gpu.csv none.log) && rc=0 || rc=$?
[[ $rc -eq 1 && $out == *"NO COUNTERS READ"* ]] || { echo "scripts_test: hw_counters_check.py: rc $rc, $out"; exit 1; }
# gpu-check --render writes no image into OUT (three 1080p PFMs, 75 MB, would keep OUT from coming back).
(step() { shift 2; echo "$*"; }; OUT_DIR=out raycoh=raycoh scene=s res=1920x1080 prefix=()
  source "$scripts/gpu-check-steps" && render_steps) > render-steps.txt
[[ $(grep -c -- "--out /tmp/" render-steps.txt) -eq 6 ]] && ! grep -q "out/" render-steps.txt ||
  { echo "scripts_test: gpu-check --render writes into OUT: $(cat render-steps.txt)"; exit 1; }
# hw_counters_check.py --modeled/--more: the modeled-vs-measured table from a committed prediction and the counter
# rows of more methods (the ncu comparison keeps HW.csv's own rows).
{ echo "scene,method,tracer,tracer_params,rays,run_under,hw_l1_hit_pct,hw_l2_hit_pct,hw_l1_wavefronts_per_ray,hw_dram_bytes_per_ray,device"
  echo "s,noopt,cuda,\"counters=hw,bvh=bvh2\",100,cupti-counters,50,80,20,30,NVIDIA H200"; } > hw-one.csv
sed 's/^s,noopt,/s,ours,/; s/,50,80,20,30,/,60,85,12,20,/' hw-one.csv > hw-all.csv
{ echo "scene,method,tracer,rays,fetches_per_ray,l1_misses_per_ray,l2_misses_per_ray,modeled_l1_wavefronts_per_ray,dram_bytes_per_ray"
  echo "s,noopt,simt,100,10,5,1,18,25"; echo "s,ours,simt,100,10,4,1,11,16"; echo "s,mlhcc,simt,100,10,4,1,11,16"; } > pred.csv
out=$(/usr/bin/python3 "$scripts/hw_counters_check.py" hw-one.csv none.log --modeled pred.csv --more hw-all.csv) || true
[[ $out == *"MODELED (simt, the prediction pred.csv) vs MEASURED"* && $out == *"| noopt | 18.0 / 20.0 | 50.0 / 50.0 | 80.0 / 80.0 | 25.0 / 30.0 |"* &&
  $out == *"| ours | 11.0 / 12.0 | 60.0 / 60.0 | 75.0 / 85.0 | 16.0 / 20.0 |"* && $out == *"not measured (no cuda:counters=hw row): mlhcc"* ]] ||
  { echo "scripts_test: hw_counters_check.py --modeled/--more: $out"; exit 1; }
expect_error "--modeled gone.csv: no such file" /usr/bin/python3 "$scripts/hw_counters_check.py" hw-one.csv none.log --modeled gone.csv
# stage_counters.py compare: a kernel's measured make-up (an ncu --page raw log) beside the prediction's; the section
# layout's instruction count is derived from its occupancy and cycles per instruction.
{ echo "kind,preset,gbuffer,file,scene,method,kernel,warps,cycles_per_warp,bytes_per_warp,l1_wavefronts_per_warp,resident_warps,chain_cycles"
  echo "modeled,h200,wide64,t.csv,sibenik,noopt,gen,100,700,3000,100,32,3500"; } > counters-pred.csv
{ echo '"ID","Kernel Name","Block Size","Grid Size","smsp__inst_executed.sum","smsp__average_warp_latency_per_inst_issued.ratio","sm__warps_active.avg.per_cycle_active","l1tex__data_pipe_lsu_wavefronts.sum","smsp__average_warps_issue_stalled_barrier_per_issue_active.ratio","dram__bytes_read.sum","dram__bytes_write.sum"'
  echo '"","","","","inst","cycle","warp","","ratio","byte","byte"'
  echo '"0","noopt_kernel(const ShadingPoint *)","(64, 1, 1)","(50, 1, 1)","50,000","10","30","12,000","2.5","1","1"'
  echo '"1","noopt_kernel(const ShadingPoint *)","(64, 1, 1)","(50, 1, 1)","100,000","14","30","25,000","3.5","200,000","100,000"'; } > raw.log
{ echo '"ID","Kernel Name","Block Size","Grid Size","Section Name","Metric Name","Metric Unit","Metric Value","Rule Description"'
  for m in '"SM Active Cycles","","70,000"' '"Achieved Active Warps Per SM","","20"' '"Warp Cycles Per Issued Instruction","","14"' '"# SMs","","1"'; do
    echo "\"0\",\"noopt_kernel(int)\",\"(64, 1, 1)\",\"(50, 1, 1)\",\"S\",$m,\"\""; done; } > sections.log
out=$(/usr/bin/python3 "$scripts/stage_counters.py" compare counters-pred.csv raw.log=noopt sections.log@0=noopt)
[[ $out == *"| noopt | gen | 1,000 | 700 | 0.70 | 14.0 | 14,000 | 3,500 | 0.25 | —, 30.0 | 32 | 250.0 | 100.0 | — | — | — | — |"* &&
  $out == *"| noopt | gen | 1,000 (derived) | 700 | 0.70 | 14.0 | 14,000 | 3,500 | 0.25 |"* &&
  $out == *"- noopt, gen: barrier 3.5 (of 14.0 cycles per issued instruction)"* &&
  $out == *"| noopt | gen | 3,000 | — | 3,000 | 1.00 |"* ]] ||
  { echo "scripts_test: stage_counters.py compare: $out"; exit 1; }
expect_error "give each log as LOG=METHOD" /usr/bin/python3 "$scripts/stage_counters.py" compare counters-pred.csv raw.log
expect_error "gone.log: no such file" /usr/bin/python3 "$scripts/stage_counters.py" compare counters-pred.csv gone.log=noopt
# stage_regions.py: a kernel's per-instruction executions and stall samples (ncu's source page) summed by the
# regions of count-stage-paths --listing, per warp of the launch in an ncu log; a foreign binary is refused.
printf '%s\n' "# arch sm_90: noopt_kernel SASS" "0x0000 LDC common" "0x0010 FFMA lobe_diffuse" "0x0020 FFMA lobe_glossy" \
  "0x0030 EXIT common" > listing.txt
{ echo '"Kernel Name","noopt_kernel"'
  echo '"Address","Source","Instructions Executed","Warp Stall Sampling (All Samples)","stall_long_sb","stall_wait"'
  echo '"7f0000","LDC R1, c[0x0][0x28]","100","50","40","10"'
  echo '"7f0010","@P0 FFMA R2, R3, R4, R5","100","30","0","30"'
  echo '"7f0020","FFMA R2, R3, R4, R5","10","0","0","0"'
  echo '"7f0030","EXIT","100","20","0","20"'
  echo '"7f0040","NOP","0","0","0","0"'; } > source.csv
out=$(/usr/bin/python3 "$scripts/stage_regions.py" source.csv listing.txt --warps-from raw.log)
[[ $out == *"| common | 2 | 2.0 | 70.0 | long_sb 57%, wait 43% |"* && $out == *"| lobe_diffuse | 1 | 1.0 | 30.0 | wait 100% |"* &&
  $out == *"| lobe_glossy | 1 | 0.1 | 0.0 | — |"* && $out == *"| all | 4 | 3.1 | 100.0 | |"* ]] ||
  { echo "scripts_test: stage_regions.py: $out"; exit 1; }
sed 's/"7f0010","@P0 FFMA/"7f0010","IMAD/; s/"7f0020","FFMA/"7f0020","IADD3/' source.csv > foreign.csv
expect_error "differ from the listing's opcodes" /usr/bin/python3 "$scripts/stage_regions.py" foreign.csv listing.txt --warps-from raw.log
expect_error "no SASS rows" /usr/bin/python3 "$scripts/stage_regions.py" listing.txt listing.txt --warps-from raw.log
# mlhcc_key_l1.py measured: the key launch's L1 counters per warp (the last launch: the timed pass).
{ echo '"ID","Kernel Name","Block Size","Grid Size","l1tex__t_requests_pipe_lsu_mem_global_op_ld.sum","l1tex__t_sectors_pipe_lsu_mem_global_op_ld.sum","l1tex__t_sectors_pipe_lsu_mem_global_op_ld_lookup_miss.sum","l1tex__t_sector_hit_rate.pct","lts__t_bytes.sum","dram__bytes_read.sum"'
  echo '"0","void key_kernel<(KeyKind)6>(RayView)","(256, 1, 1)","(4, 1, 1)","1","1","1","1","1","1"'
  echo '"1","void key_kernel<(KeyKind)6>(RayView)","(256, 1, 1)","(4, 1, 1)","14,400","86,400","3,456","95.5","112,000","32,000"'; } > key.log
out=$(/usr/bin/python3 "$scripts/mlhcc_key_l1.py" measured key.log raw.log)
[[ $out == *"| key.log | 450.0 | 2,700 | 108.0 | 96.00 | 95.50 | 3,500 | 1,000 |"* && $out == *"| raw.log | no key_kernel launch |"* ]] ||
  { echo "scripts_test: mlhcc_key_l1.py measured: $out"; exit 1; }
expect_error "gone.log: no such file" /usr/bin/python3 "$scripts/mlhcc_key_l1.py" measured gone.log
# gpu-check --stages under Nsight Compute: one log per method, named by its label, each method's generator and encoder.
(cd "$scripts/.." && step() { echo "$1 ${*:3}"; } && OUT_DIR=out raycoh=raycoh scene=s res=1920x1080 prefix=() &&
  source scripts/gpu-check-steps && ncu_path() { echo ncu; } && stage_counter_steps) > counter-steps.txt
[[ $(grep -c "^ncu-stage-[a-z_0-9]* env" counter-steps.txt) -eq 5 ]] &&
  grep -q "^ncu-stage-noopt_mlhcc-conference .*--scenes \./conference .*--encoders mlhcc" counter-steps.txt &&
  grep -q "^mlhcc-key-l1 .*mlhcc_key_l1.py measured out/ncu-stage-noopt_mlhcc.log out/ncu-stage-noopt_mlhcc-conference.log out/ncu-stage-noopt_mlhcc-country_kitchen.log$" counter-steps.txt &&
  [[ $(grep -c "^ncu-stage-source-\(noopt\|ours\) .*--section SourceCounters" counter-steps.txt) -eq 2 ]] &&
  [[ $(grep -c "^ncu-stage-source-\(noopt\|ours\)-csv .*--page source --csv --print-source sass" counter-steps.txt) -eq 2 ]] &&
  grep -q "^ncu-stage-ours_tile_32x8_k_8_order_tile .*--generators ours:tile=32x8,k=8 --encoders none" counter-steps.txt &&
  grep -q "^ncu-stage-noopt_mlhcc .*--generators noopt --encoders mlhcc" counter-steps.txt ||
  { echo "scripts_test: gpu-check stage counter steps: $(cat counter-steps.txt)"; exit 1; }
echo "scripts_test: all plot scripts wrote their figures"
