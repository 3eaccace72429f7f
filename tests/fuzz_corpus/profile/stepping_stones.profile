# Stepping stones across a stream: stones 0.32–0.5 m long with 0.2–0.45 m of water between.
start 0
goal 6.8
ground -0.5 0    1.2 0
ground  1.5 0.05 1.9 0.05
ground  2.3 0.02 2.65 0.02
ground  2.95 0.08 3.45 0.08
ground  3.9 0.04 4.22 0.04
ground  4.5 0.0  4.9 0.0
ground  5.3 0.06 5.7 0.06
ground  6.0 0    8 0
