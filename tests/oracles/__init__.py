"""The sub-packages of tests hold verification oracles that only tests and studies import."""
