// Fuzz target: the generated Python module's argument parsing. A pendulum's module
// (Scalar_dynamics, generated from tests/python/hostile_pendulum.urdf at build time) is linked in
// and imported by an embedded interpreter; fuzz_python.py makes a call of it from the bytes and
// checks the outcome. A Python exception out of the driver is a finding.
#include <pybind11/embed.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>

namespace py = pybind11;

extern "C" PyObject* PyInit_Scalar_dynamics();

namespace {

/// The driver's run(data), from an interpreter started on the first call and never finalised
/// (NumPy does not support a second start, and the process ends anyway).
const py::object& driver() {
  static const py::object* run = [] {
    // Python's objects in malloc's memory, not in arenas of its own: the sanitizers see their
    // accesses, and the leak check follows the pointers they hold
    PyPreConfig config;
    PyPreConfig_InitPythonConfig(&config);
    config.allocator = PYMEM_ALLOCATOR_MALLOC;
    Py_PreInitialize(&config);
    PyImport_AppendInittab("Scalar_dynamics", &PyInit_Scalar_dynamics);
    py::initialize_interpreter();
    py::module_::import("sys").attr("path").attr("insert")(0, DYNGEN_FUZZ_DIR);
    return new py::object(py::module_::import("fuzz_python").attr("run"));
  }();
  return *run;
}

}  // namespace

/// The leak check's suppressions: Python's own objects, which the interpreter, never finalised,
/// holds at exit through pointers the check does not follow. A reference the module leaks
/// shows in the arguments' reference counts, which fuzz_python.py checks after every call.
extern "C" const char* __lsan_default_suppressions() { return "leak:libpython3\n"; }

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  try {
    driver()(py::bytes(reinterpret_cast<const char*>(data), size));
  } catch (const py::error_already_set& e) {
    std::fprintf(stderr, "fuzz finding: %s\n", e.what());
    std::abort();
  }
  return 0;
}
