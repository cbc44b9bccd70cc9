"""What each engine command does beyond calling its stage: the settings of the commands that have no stage
config of their own, and the line each tells the user. engine.cli lists the commands; this package runs them.
May import every stage."""
