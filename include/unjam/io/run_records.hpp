// The records of a long run, one module for every command that keeps them (`unjam perturb
// -o DIR`, `unjam bounds -o FILE`; docs/format.md): a JSON Lines file (json_lines.hpp) whose
// header names the run's parameters, one record appended per result as it is obtained. A
// rerun of the same command takes the records back and does only the rest; a file of other
// parameters is refused. Under mpirun rank r appends to its own file beside the main one
// (RankPath), and rank 0 merges them once every rank is done.
#pragma once

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace unjam {

class RunRecords {
 public:
  struct Entry {
    std::filesystem::path file;
    int line = 0;
    nlohmann::json record;
    std::string Where() const { return file.string() + ":" + std::to_string(line); }
  };

  // Reads every rank file beside `path` (a file of another header is a usage error naming
  // it and `remedy`; a bad line an InputError naming file and line), cuts a torn last line
  // off this rank's own file, and opens that file for appending.
  RunRecords(std::filesystem::path path, nlohmann::json header, int rank, std::string remedy);

  // The records on disk when read (construction or the last Merge), in file order.
  const std::vector<Entry>& Entries() const { return entries_; }
  const std::filesystem::path& Path() const { return path_; }
  // Appends one record and flushes it. Throws OutputError if it cannot write.
  void Append(const nlohmann::json& record);
  // This rank's file is complete (no more Append).
  void Close() { own_file_.close(); }
  // Whether other ranks' files lie beside the main one (an mpirun, or one interrupted).
  bool HasRankFiles() const;
  // Rank 0, once every rank is done: the rank files in the main one, and Entries() all the
  // records, this run's too.
  void Merge();
  // The run is written out: the records, rank files included, are removed.
  void Remove();

 private:
  void Read(bool cut_own);

  std::filesystem::path path_, own_;
  nlohmann::json header_;
  std::string remedy_;
  std::ofstream own_file_;
  std::vector<Entry> entries_;
};

}  // namespace unjam
