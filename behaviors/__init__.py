"""behaviors: the three engines, as pure functions over numpy arrays with thin stateful engines."""
