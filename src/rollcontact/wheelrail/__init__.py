"""Wheel on rail from real profiles: profiles, contact geometry, tread and flange patches, non-Hertzian contact.

Track axes (docs/physics.md, Wheel/rail contact): x along the track in the direction of travel, y lateral to the
right, z downward (right-handed, the Manchester Contact Benchmark's and CONTACT's axes).
"""
