// The output folder of a run or a study, created up front so that a path that cannot hold one
// is refused as bad input before any work; and what a run may delete: only what it can prove a
// run wrote. A run folder carries a manifest (.contact2d-run) naming every file the run wrote;
// a run's work folder carries a marker (.contact2d-work) naming its process.
#pragma once

#include <string>
#include <vector>

namespace c2d::app {

/// The manifest of a run folder: "contact2d run folder", "run ID", then one file name a line.
inline constexpr const char* kRunManifest = ".contact2d-run";
/// The marker of a work folder (TARGET.part.PID): "contact2d work folder", "pid PID".
inline constexpr const char* kWorkMarker = ".contact2d-work";

/// Throws InputError naming `dir` when it names an existing file (a folder, or nothing yet, is
/// fine).
void refuse_file_as_folder(const std::string& dir);

/// Throws InputError naming `dir` when a run may not replace it whole: a name with control
/// characters, a folder holding the current folder (".", "..", "/"), a folder holding one of
/// `inputs` (the scene, its .msh files), or an existing folder that is neither empty nor an
/// earlier run's: every entry a regular file its manifest lists (a study worker's stdout.log
/// aside). A run replaces its output folder, so pointing --out at a project folder would
/// delete its files.
void refuse_foreign_folder(const std::string& dir, const std::vector<std::string>& inputs = {});

/// Creates `dir` (and its parents) if needed. Throws InputError naming `dir` when it names an
/// existing file or cannot be created (permissions, a file on the path).
void create_output_folder(const std::string& dir);

/// Writes `dir`'s manifest listing every regular file now in it (the folder is a run's own
/// work folder, so everything in it is the run's) and the `coming` names it will write.
void write_run_manifest(const std::string& dir, const std::string& run_id,
                        const std::vector<std::string>& coming = {});

/// Adds `names` (files a later verb such as plot wrote into run folder `dir`) to its manifest,
/// so the next run into `dir` may replace them; no-op for a folder without a manifest.
void add_to_run_manifest(const std::string& dir, const std::vector<std::string>& names);

/// The file names the manifest of `dir` lists (empty without one).
std::vector<std::string> run_manifest_names(const std::string& dir);

/// Removes the files the manifest of `dir` lists, the manifest, and the folder when nothing
/// else is left; anything else stays. True when the folder is gone.
bool remove_run_folder(const std::string& dir);

/// Creates `dir` as a folder of this process's own (TARGET.part.PID): fails (false) when it
/// exists already; writes its marker.
bool create_work_folder(const std::string& dir);

/// The process that owns work folder `dir` per its marker; -1 without a valid marker.
long work_folder_owner(const std::string& dir);

}  // namespace c2d::app
