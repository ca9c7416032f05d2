"""The compile's stages as library functions with typed settings (:mod:`vc.stages.config`): render, train,
export, self-test, evaluate, and the compile that runs them in turn. The commands (:mod:`vc.cli`), the benchmarks and
the tests call these; none of them runs another command's argument parser."""
