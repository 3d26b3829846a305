#!/usr/bin/env bash
# rsf diagnose on every laboratory record in ../shared/data (the bundled basalt record needs
# nothing else). Run from the repository root:  bash docs/diagnose/make.sh
# Writes NAME.json, NAME.html (the report) and NAME.txt (the console summary) per record.
set -euo pipefail
cd "$(dirname "$0")/../.."
cargo build --release -q -p rsf-cli
R=target/release/rsf
S=../shared/data
G=$S/giacomel-steadystate
O=docs/diagnose
BAS=(--time-col "Time(s)" --lp-col "Displ(microns)" --mu-col Friction)
run() { local name=$1; shift; echo "== $name"; "$R" diagnose "$@" --json "$O/$name.json" --report "$O/$name.html" | tee "$O/$name.txt"; }
# Giacomel et al.: basalt (BRAVA, σn 20 MPa; apparatus k 0.3015 MPa/µm = 0.0151/µm) and
# sepiolite (TR2, σn 30 MPa)
run basalt4 examples/data/giacomel-basalt/velstep4_BRAVA_expb819_basalt.txt "${BAS[@]}" --stiffness 0.0151
run basalt7 "$G/main-history/velstep7_BRAVA_expb819_basalt.txt" "${BAS[@]}" --stiffness 0.0151
# the same step with displacement corrected for the apparatus: nominally rigid (k = 1/µm)
run basalt7_corrected "$G/main-history/velstep7_BRAVA_expb819_basalt_Giacomel_et_al_2021.txt" "${BAS[@]}" --stiffness 1
run sepiolite1 "$G/main-history/velstep1_TR2_exp013_sepiolite.txt" "${BAS[@]}" --stiffness 0.01
run sepiolite2 "$G/main-history/velstep2_TR2_exp013_sepiolite.txt" "${BAS[@]}" --stiffness 0.01
run sepiolite3 "$G/main-history/velstep3_TR2_exp013_sepiolite.txt" "${BAS[@]}" --stiffness 0.01
# Leeman et al. 2016, p4309 (quartz gouge, σn 8 MPa); stiffness from the lab's xlook fits
run p4309_down "$S/leeman2016-p4309/step_2_model.txt" --time-col Time --lp-col LP_Disp --stiffness 0.0028
run p4309_up "$S/leeman2016-p4309/step_35_model.txt" --time-col Time --lp-col LP_Disp --stiffness 0.0055
# Penn State p655 (σn 100 MPa; the lab's calibrated machine stiffness 0.1 MPa/µm = 1e-3/µm)
run p655_step "$S/psu-xlook-examples/p655intact100_reduced.csv" --lp-col lp_disp_um --t-min 3844.4 --t-max 3859.4 --stiffness 1e-3
run p655_step23 "$S/psu-xlook-examples/p655intact100_reduced.csv" --lp-col lp_disp_um --t-min 3870 --t-max 3878.9 --stiffness 1e-3
# the 47 s load-point stop at 74.7 MPa: a slide-hold-slide (k = 0.1/74.7)
run p655_hold "$S/psu-xlook-examples/p655intact100_reduced.csv" --lp-col lp_disp_um --t-min 2560 --t-max 2760 --stiffness 1.34e-3
# Penn State p446 (till), the staircase 1 → 300 → 1 µm/s at σn 10 MPa (k = 0.1/10)
run p446_10mpa "$S/psu-xlook-examples/p446s7tr005_reduced.csv" --lp-col lp_disp_um --t-min 2900 --t-max 4094 --stiffness 0.01
