# The anchoring cue before an exercise, for a patient who neglects one side of space.
# Spoken from that side while a bar lights its edge.
neglect-look-here = Look over here.
