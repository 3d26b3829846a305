#!/usr/bin/env bash
# rsf diagnose on the real records (needs ../shared/data for the unlicensed ones).
# Run from the repository root:  bash docs/diagnose/make.sh
set -euo pipefail
cd "$(dirname "$0")/../.."
cargo build --release -q -p rsf-cli
R=target/release/rsf
S=../shared/data
O=docs/diagnose
BAS=(--time-col "Time(s)" --lp-col "Displ(microns)" --mu-col Friction)
run() { local name=$1; shift; echo "== $name"; "$R" diagnose "$@" --json "$O/$name.json" --report "$O/$name.html" | tee "$O/$name.txt"; }
run basalt4 examples/data/giacomel-basalt/velstep4_BRAVA_expb819_basalt.txt "${BAS[@]}" --stiffness 0.0151
run basalt7 "$S/giacomel-steadystate/main-history/velstep7_BRAVA_expb819_basalt.txt" "${BAS[@]}" --stiffness 0.0151
run sepiolite3 "$S/giacomel-steadystate/demo-branch/velstep3_TR2_exp013_sepiolite.txt" "${BAS[@]}" --stiffness 0.01
run p4309_down "$S/leeman2016-p4309/step_2_model.txt" --time-col Time --lp-col LP_Disp --stiffness 0.0028
run p4309_up "$S/leeman2016-p4309/step_35_model.txt" --time-col Time --lp-col LP_Disp --stiffness 0.0055
run p655_step "$S/psu-xlook-examples/p655intact100_reduced.csv" --lp-col lp_disp_um --t-min 3844.4 --t-max 3859.4 --stiffness 1.6e-3
