// The fuzz targets for double (see fuzz_targets.hpp).
#include "fuzz_targets.hpp"

template void neurov_fuzz::fuzz_one<double>(FuzzedDataProvider&);
