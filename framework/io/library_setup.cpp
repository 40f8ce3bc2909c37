#include "framework/io/library_setup.hpp"

#include <hdf5.h>
#include <vtkObject.h>

namespace rockdem {

void quiet_io_libraries() {
  H5dont_atexit();  // must come before the first HDF5 call
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  vtkObject::GlobalWarningDisplayOff();
}

}  // namespace rockdem
