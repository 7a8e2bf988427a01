// The fuzz targets for float (see fuzz_targets.hpp).
#include "fuzz_targets.hpp"

template void neurov_fuzz::fuzz_one<float>(FuzzedDataProvider&);
