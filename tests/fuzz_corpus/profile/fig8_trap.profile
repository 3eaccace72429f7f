# The trap of seed 002 Fig 8: walking at the nominal 0.65 m step, the actor arrives at the edge
# of a 0.6 m gap with its front foot too far back to stride across (Fig 8 (a)); the footstep
# planner sees the gap three steps ahead and shortens its steps so that the last foothold
# before the gap is close enough to the edge (Fig 8 (b)).
start 0
goal 6
ground -0.5 0 3.0 0
ground  3.6 0 8.0 0
