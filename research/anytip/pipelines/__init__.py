"""One module per kind of experiment; each has `run(ctx) -> rows`."""
