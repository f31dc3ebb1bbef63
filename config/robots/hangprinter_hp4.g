; Hangprinter v4 (HP4) as RepRapFirmware configures it: the source of hangprinter_hp4.yaml
; (`cdpr import rrf --config config/robots/hangprinter_hp4.g --out config/robots/hangprinter_hp4.yaml
;  --name HP4`). Values from data/hangprinter/hp4_2022_force_series2.json: the anchors are the
; author's rough manual estimate (hand_anchors_rough_mm), an uncalibrated starting point; the
; machine constants (machine_constants): gear teeth 20 / 255, mechanical advantage 2, 2, 2, 4, one
; line per spool, spool radius first guess 75 mm, the buildup factor the author used (0.06875 mm),
; line stiffness per unit length 20 kN, mover weight 2 kg.
M669 K6 A0:-1620:-150 B1272.79:1272.79:-150 C-1402.96:810:-150 D0:0:2350
M666 Q0.06875 R75:75:75:75 U2:2:2:4 O1:1:1:1 L20:20:20:20 H255:255:255:255 W2 S20000
