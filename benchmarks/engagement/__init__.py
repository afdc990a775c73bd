"""Engagement: the labelled recordings through the real path, the cross-validation by
person, simulated people against hri_engagement's rule, and their pages."""
