#pragma once
// The names a cost table's rows give their targets (rows[].backend, the keys of rows[].gpu) checked against
// the lists aovar knows, before anything chooses by them or writes them into generated code: a table may
// come from another machine (a shard, a CI artefact), and a name is only ever one of those lists.
#include <string>

#include "table/table.h"

namespace aovar::decide {

// A GPU aovar knows: one of Mesa's AMD families (compile/amd_devices.h) or a family, alias or product of
// src/gpu/families.json (the GL chips included).
bool is_known_gpu(const std::string& name);
// A backend of the render registry (render::backend_names()).
bool is_known_backend(const std::string& name);

// Throws std::runtime_error, one line naming the table, the row (index and key) and the name: a row whose
// backend is not a registered backend, or whose "gpu" object has a key that is no known GPU.
void check_row_targets(const table::CostTable& table, const std::string& table_name);

}  // namespace aovar::decide
