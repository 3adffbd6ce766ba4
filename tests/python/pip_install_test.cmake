# ctest -P script: `pip install --no-build-isolation` of a --torch package (dyngen DYNGEN, robot
# INPUT) for PYTHON, into SCRATCH/site (--target, and --no-deps: NumPy and torch are the
# system's, and pip would look for them online), then the installed module imported from there
# and its rnea checked against its crba and nle (tau = M a + h), and the installed
# installed_torch.py's rnea against the module's. pip's build stays in the package's build-pip/, a
# CMake build tree, so that dyngen can still replace the package: it is generated again there.
# SCRATCH is rewritten.
file(REMOVE_RECURSE ${SCRATCH})
foreach(step IN ITEMS generate install use regenerate)
  if(step STREQUAL "generate" OR step STREQUAL "regenerate")
    set(cmd ${DYNGEN} ${INPUT} -o ${SCRATCH}/package --name installed --quiet --torch
            --algorithms rnea,crba,nle)
  elseif(step STREQUAL "install")
    set(cmd ${PYTHON} -m pip install --no-build-isolation --no-deps --no-index --quiet
            --target ${SCRATCH}/site ${SCRATCH}/package)
  else()
    set(cmd ${CMAKE_COMMAND} -E env PYTHONPATH=${SCRATCH}/site ${PYTHON} -c [=[
import numpy as np, installed_dynamics as d
assert d.__file__.startswith(d.__file__.split("/site/")[0] + "/site/"), d.__file__
rng = np.random.default_rng(3)
q, v, a = (rng.uniform(-2, 2, (5, n)) for n in (d.nq, d.nv, d.nv))
tau = d.rnea(q, v, a)
reference = np.einsum("sij,sj->si", d.crba(q), a) + d.nle(q, v)
assert np.max(np.abs(tau - reference)) <= 1e-12 * np.max(np.abs(reference))
import torch, installed_torch as t
assert t.__file__.startswith(d.__file__.split("/site/")[0] + "/site/"), t.__file__
assert np.array_equal(t.rnea(*(torch.from_numpy(x) for x in (q, v, a))).numpy(), tau)
print("installed at", d.__file__, "and", t.__file__)
]=])
  endif()
  execute_process(COMMAND ${cmd} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE out)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "${step} failed:\n${out}")
  endif()
  message(STATUS "${step}:\n${out}")
endforeach()
file(GLOB left RELATIVE ${SCRATCH}/package ${SCRATCH}/package/*)
list(FILTER left EXCLUDE
     REGEX "^(installed_.*|dyngen_sincos\\.h|CMakeLists\\.txt|pyproject\\.toml|setup\\.py|build-pip)$")
if(left OR NOT EXISTS ${SCRATCH}/package/build-pip/CMakeCache.txt)
  message(FATAL_ERROR "pip left ${left} in the package, or no build tree build-pip/")
endif()
