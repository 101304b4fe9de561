"""Reports for reviewers and CI: a neutral findings model, its JUnit, SARIF and GitHub writers, the markdown diff."""
