# Stairs up and down: four steps of 0.17 m on 0.30 m treads up to a 1.5 m landing, then four
# steps down. Walking is toward +X; heights in metres.
start 0
goal 7.5
ground -0.5 0    2.0 0
ground  2.0 0.17 2.3 0.17
ground  2.3 0.34 2.6 0.34
ground  2.6 0.51 2.9 0.51
ground  2.9 0.68 4.4 0.68   # landing
ground  4.4 0.51 4.7 0.51
ground  4.7 0.34 5.0 0.34
ground  5.0 0.17 5.3 0.17
ground  5.3 0    8.5 0
