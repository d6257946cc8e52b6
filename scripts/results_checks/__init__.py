"""scripts/check-results: every figure quoted in a results README recomputed from the CSV rows it comes from."""
