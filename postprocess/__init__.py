"""Engine dumps -> T, A, eps -> comparison with the reference -> report."""
