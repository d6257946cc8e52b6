// What `raycoh merge` (harness/merge.cpp) tells the merge of the commands whose files it joins: their defaults for
// options a recorded command line does not give. Also used by the shard_merge fuzz target (tests/fuzz/).
#pragma once

#include "records/merge.h"

namespace raycoh {

MergeCommands merge_command_defaults();

}  // namespace raycoh
