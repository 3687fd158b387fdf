"""Speed-versus-accuracy benchmarks against the peers (not part of the test suite)."""
