# A slope up at 15°, a plateau, and a slope down at 20°.
start 0
goal 9
ground -0.5 0     1.5 0
ground  1.5 0     4.5 0.804   # 3 m at 15°: rise 3 · tan 15°
ground  4.5 0.804 5.5 0.804
ground  5.5 0.804 7.5 0.076   # 2 m at 20°: drop 2 · tan 20°
ground  7.5 0.076 10  0.076
