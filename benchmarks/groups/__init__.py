"""Groups: F-formations held out by dataset, scenes made from how grouping failed, ideas
kept or dropped, the live service, and where to stand."""
