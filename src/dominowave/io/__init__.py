"""Study files, result folders, checkpoints, trajectories, VTK, animation, provenance.

Nothing here simulates: these modules read and write what the scenarios compute.
"""
