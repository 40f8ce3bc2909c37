#pragma once
// Process-wide settings of the I/O libraries, made once by main() before any file is touched.

namespace rockdem {

// HDF5 and VTK print their own diagnostics (pages of HDF5 error stacks, VTK pipeline dumps) when
// a write fails; rockdem reports every failure itself with the path, so these are switched off.
// HDF5's at-exit clean-up is switched off too: after a failed write (disk full) it closed the file
// a second time and crashed (SIGSEGV in H5F__close_cb) after the error had been reported; every
// file rockdem opens is closed by its owner, so there is nothing left for it to do.
void quiet_io_libraries();

}  // namespace rockdem
