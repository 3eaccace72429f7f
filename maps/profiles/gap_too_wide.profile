# A gap of 1.2 m: wider than the longest step (0.9 m) can cross with the whole sole on both
# sides. The walker goes as far as it can and stops at the edge.
start 0
goal 6
ground -0.5 0 3.0 0
ground  4.2 0 8.0 0
