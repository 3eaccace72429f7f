# Low obstacles lying on the path: a 0.15 m plank to step over or onto, a 0.4 m box to step
# onto and off, and a 0.25 m kerb up to a raised walk.
start 0
goal 8
ground -0.5 0    1.5 0
ground  1.5 0.15 1.7 0.15   # plank
ground  1.7 0    3.0 0
ground  3.0 0.4  3.6 0.4    # box
ground  3.6 0    5.2 0
ground  5.2 0.25 9.0 0.25   # kerb and raised walk
