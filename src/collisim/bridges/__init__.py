"""Bridges to other tools, each an optional extra that `import collisim` never loads.

    collisim.bridges.manim   TrajectoryMobject: a collisim Trajectory playing inside a manim scene
                             (pip install 'collisim[manim]')
"""
