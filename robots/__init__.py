"""The course robots' URDFs (installed as ``course_dynamics_robots``); see README.md here and course_dynamics.core.robots."""
