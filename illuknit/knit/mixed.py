"""Mixed-colourwork scheduler (work in progress, issue 6).

Schedules patterns whose courses change colour inside the course (double-view
and head-on illusions): colour runs, float avoidance (paper Algorithm 1),
catching by plating (Algorithm 2) and yarn path planning (Algorithm 3), with
the fewest carriage passes.
"""
