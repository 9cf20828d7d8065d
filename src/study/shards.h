// Sharding a study over machines (issue 14). Shard I of N (`restir study ... --shard I/N`) runs the
// jobs at positions p of the study's job list with p % N == I (the list is the same on every
// machine: scenes x configurations x seeds in the study file's order), skipping jobs that any part
// already holds, and keeps its rows in its own store DIR/shards/I-of-N/results.json, so shards on
// a shared file system never write the same file. `--merge` (or any run without --shard) reads
// the main store and every part; renders/ and images/ are per job, references/ are locked.
#pragma once
#include <string>
#include <vector>

#include "study/results.h"

namespace rl::study {

struct ShardSpec {
  int index = -1, count = 0;  // count == 0: not sharded
  bool active() const { return count > 0; }
  bool owns(size_t job_position) const { return !active() || int(job_position % size_t(count)) == index; }
};

// Parses "I/N" (0 <= I < N); throws StudyError naming --shard otherwise.
ShardSpec parse_shard(const std::string& text);
// DIR/shards/I-of-N: the folder of shard I's store.
std::string shard_dir(const std::string& out, const ShardSpec& shard);
// Rows of every shard store under DIR/shards (any N), in folder-name order.
std::vector<Row> load_shard_rows(const std::string& out, const std::vector<std::string>& metric_columns,
                                 const std::string& study);
// The rows of `a` then those of `b` that `a` does not hold (same id and frame).
std::vector<Row> union_rows(std::vector<Row> a, const std::vector<Row>& b);

}  // namespace rl::study
