# A cliff: the ground drops 1.5 m, three times the deepest step down. The walker stops at the
# edge.
start 0
goal 7
ground -0.5  0   4.0 0
ground  4.0 -1.5 9.0 -1.5
