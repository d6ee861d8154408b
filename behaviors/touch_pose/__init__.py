"""Multi-touch pose control."""
