; RepRapFirmware lines (config.g) of the best model of each session of the Hangprinter study
; (hangprinter; written by cdpr calibrate study, cdpr.pipeline.hangprinter; nominal robot config/robots/hangprinter_hp4.yaml)

; hp4_2022_force_series2: rigid lines, anchors + spools (rigid_spools), fitted on all samples; held-out position RMS 2.26 mm with 44 folds
; warning: RepRapFirmware has one buildup factor per machine: M666 Q is the mean 0.101008 mm of the cables' 0.138334, 0.0622024, 0.146064, 0.0574306 mm
M669 K6 A17.206:-1579.524:-109.520 B1302.546:1243.959:-165.217 C-1405.335:741.149:-145.765 D25.267:-0.506:2369.874
M666 Q0.101008 R75.967:76.089:75.937:75.870 U2:2:2:4 O1:1:1:1 L20:20:20:20 H255:255:255:255 W2.000 S20000.00 X70.0:70.0:70.0:70.0 Y2978.993:3080.583:2978.993:0.000

; hp4_2021_12_grid: + everything identified (buildup factor free) (everything), fitted on all samples; held-out position RMS 1.41 mm with 25 folds
; warning: RepRapFirmware has one buildup factor per machine: M666 Q is the mean 0.110161 mm of the cables' 0.117441, 0.111387, 0.166598, 0.0452196 mm
M669 K6 A14.152:-1621.561:-125.580 B1315.076:1249.148:-172.855 C-1422.742:744.545:-150.871 D24.444:2.913:2340.162
M666 Q0.110161 R75.960:75.863:75.603:75.703 U2:2:2:4 O1:1:1:1 L20:20:20:20 H255:255:255:255 W2.000 S20000.00 X70.0:70.0:70.0:70.0 Y2978.993:3080.583:2978.993:0.000

; hp3_2018: no held-out measured position, so no best model: no firmware lines
