#!/usr/bin/env bash
# Fits of the real records (docs/fit.md). Needs ../shared/data beside the checkout for the
# unlicensed records; the bundled basalt record is in examples/data.
# Run from the repository root:  bash docs/fits/make.sh
set -euo pipefail
cd "$(dirname "$0")/../.."
cargo build --release -q -p rsf-cli
R=target/release/rsf
S=../shared/data
O=docs/fits
L="$S/leeman2016-p4309"
G="$S/giacomel-steadystate"
P="$S/psu-xlook-examples/p655intact100_reduced.csv"
BAS=(--time-col "Time(s)" --lp-col "Displ(microns)" --mu-col Friction)
run() { local name=$1; shift; echo "== $name"; "$R" fit "$@" --json "$O/$name.json" --plot "$O/$name.svg" | tee "$O/$name.txt"; }

# Leeman et al. (2016) p4309: the lab's xlook Slip-law fits (k = 0.0028 down, 0.0055 up)
run p4309_down "$L/step_2_model.txt" --time-col Time --lp-col LP_Disp --law slip --stiffness 0.0028 --mcmc 20000 --seed 1
run p4309_up "$L/step_35_model.txt" --time-col Time --lp-col LP_Disp --law slip --stiffness 0.0055 --mcmc 20000 --seed 1
# Penn State p655, 100 MPa, 2.2 -> 22 µm/s (Marone's fits: Slip k = 1.6e-3, Aging k = 1e-3)
run p655_slip "$P" --lp-col lp_disp_um --t-min 3844.4 --t-max 3859.4 --law slip --stiffness 1.6e-3 --mcmc 20000 --seed 1
run p655_aging "$P" --lp-col lp_disp_um --t-min 3844.4 --t-max 3859.4 --law aging --stiffness 1e-3
run p655_slip_protocol "$P" --lp-col lp_disp_um --t-min 3844.4 --t-max 3859.4 --law slip --stiffness 1.6e-3 --loading protocol
# Giacomel basalt velstep7 (100 -> 300 µm/s, 1 kHz): load-point and elastically corrected versions, k free
run basalt7_lp "$G/main-history/velstep7_BRAVA_expb819_basalt.txt" "${BAS[@]}" --law slip --stiffness 0.0151 --fit-stiffness --loading protocol
run basalt7_corrected "$G/main-history/velstep7_BRAVA_expb819_basalt_Giacomel_et_al_2021.txt" "${BAS[@]}" --law slip --stiffness 0.0151 --fit-stiffness --loading protocol
run basalt7_lp_record "$G/main-history/velstep7_BRAVA_expb819_basalt.txt" "${BAS[@]}" --law slip --stiffness 0.0151 --fit-stiffness
# the bundled basalt velstep4 (3 -> 10 µm/s), the README's main job
run basalt4 examples/data/giacomel-basalt/velstep4_BRAVA_expb819_basalt.txt "${BAS[@]}" --law slip --stiffness 0.0151 --fit-stiffness --loading protocol --mcmc 20000 --seed 1
# sepiolite velstep3 (0.2 -> 2 µm/s, TR2), long transients
run sepiolite3 "$G/demo-branch/velstep3_TR2_exp013_sepiolite.txt" "${BAS[@]}" --law slip --stiffness 0.01 --fit-stiffness --loading protocol
run sepiolite3_2state "$G/demo-branch/velstep3_TR2_exp013_sepiolite.txt" "${BAS[@]}" --law slip --states 2 --stiffness 0.01 --fit-stiffness --loading protocol --max-iter 400
for f in "$O"/*.svg; do command -v rsvg-convert >/dev/null && rsvg-convert -w 1000 "$f" -o "${f%.svg}.png" || true; done
