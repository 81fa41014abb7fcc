// Python bindings of io: reading CARMEN logs, ROS bags and the simulator through the one scan-source entry
// point (load_scan_source: a path or "sim[:SEED]"), writing CARMEN logs, and the SQLite map database
// (datasets of submaps, dictionaries, packed descriptors and their codecs) with the decoded descriptor sets
// of io/store/descriptor_store.h. Log reading and writing release the GIL; database calls keep it, so one
// MapDatabase object is never used by two threads at once.
#include "casters.h"
// (casters.h first: see its header comment)
#include <memory>
#include <optional>

#include "bindings.h"
#include "core/error.h"
#include "io/logs/carmen_log.h"
#include "io/store/descriptor_store.h"
#include "io/store/map_database.h"
#include "io/logs/scan_source.h"

namespace partslam::python {

namespace py = pybind11;
using namespace pybind11::literals;
using release_gil = py::call_guard<py::gil_scoped_release>;

namespace {

// `with db.transaction():` — the writes inside commit together when the block ends normally, and are rolled
// back when it raises (MapDatabase::Transaction).
class TransactionScope {
 public:
  explicit TransactionScope(io::MapDatabase& db) : db_(db) {}
  void enter() {
    if (transaction_) throw InputError("transaction: already entered");
    transaction_ = std::make_unique<io::MapDatabase::Transaction>(db_);
  }
  void exit(const py::object& error_type) {
    if (transaction_ && error_type.is_none()) transaction_->commit();
    transaction_.reset();
  }

 private:
  io::MapDatabase& db_;
  std::unique_ptr<io::MapDatabase::Transaction> transaction_;
};

void define_logs(py::module_& m) {
  py::enum_<io::FlaserSpacing>(m, "FlaserSpacing", "Angle between consecutive FLASER beams")
      .value("CARMEN", io::FlaserSpacing::kCarmen)
      .value("PI_OVER_N", io::FlaserSpacing::kPiOverN)
      .value("PI_OVER_N_MINUS_1", io::FlaserSpacing::kPiOverNMinus1);
  py::class_<io::LogReadOptions> options(m, "LogReadOptions", "How logs are read (io/logs/log_read_options.h)");
  options.def_readwrite("min_range", &io::LogReadOptions::min_range, "[m]")
      .def_readwrite("max_usable_range", &io::LogReadOptions::max_usable_range, "[m]")
      .def_readwrite("no_return_range", &io::LogReadOptions::no_return_range, "[m]")
      .def_readwrite("no_return_code_share", &io::LogReadOptions::no_return_code_share,
                     "a 1 cm range bin holding this share of a recording's beams is the scanner's no-return code")
      .def_readwrite("no_return_code_min_range", &io::LogReadOptions::no_return_code_min_range, "[m]")
      .def_readwrite("flaser_spacing", &io::LogReadOptions::flaser_spacing)
      .def_readwrite("max_points", &io::LogReadOptions::max_points, "a log with more valid beams is refused")
      .def_readwrite("skip_damaged", &io::LogReadOptions::skip_damaged,
                     "skip (and count) damaged records in the middle of a log instead of raising InputError")
      .def_readwrite("max_scan_jump", &io::LogReadOptions::max_scan_jump,
                     "largest distance between consecutive scans' poses [m]")
      .def("validate", py::overload_cast<const io::LogReadOptions&>(&io::validate),
           "Raises InputError naming the field that is out of range.");
  def_keyword_init(options);

  py::class_<io::OdomReading>(m, "OdomReading", "One ODOM message")
      .def_readonly("timestamp", &io::OdomReading::timestamp)
      .def_readonly("T_world_odom", &io::OdomReading::T_world_odom)
      .def_readonly("tv", &io::OdomReading::tv)
      .def_readonly("rv", &io::OdomReading::rv)
      .def_readonly("accel", &io::OdomReading::accel);
  py::class_<io::CarmenLogStats>(m, "CarmenLogStats", "What a log held, by line and message")
      .def_readonly("lines", &io::CarmenLogStats::lines)
      .def_readonly("flaser", &io::CarmenLogStats::flaser)
      .def_readonly("robotlaser", &io::CarmenLogStats::robotlaser)
      .def_readonly("odom", &io::CarmenLogStats::odom)
      .def_readonly("comments", &io::CarmenLogStats::comments)
      .def_readonly("blank", &io::CarmenLogStats::blank)
      .def_readonly("beams", &io::CarmenLogStats::beams)
      .def_readonly("valid_beams", &io::CarmenLogStats::valid_beams)
      .def_readonly("no_return_code_beams", &io::CarmenLogStats::no_return_code_beams)
      .def_readonly("skipped", &io::CarmenLogStats::skipped, "skipped messages by name")
      .def_readonly("damaged", &io::CarmenLogStats::damaged, "damaged lines skipped (skip_damaged)")
      .def_readonly("pose_jumps", &io::CarmenLogStats::pose_jumps, "scans skipped for a pose jump (skip_damaged)")
      .def_readonly("cut_short", &io::CarmenLogStats::cut_short, "the file ended mid-record");
  py::class_<io::CarmenLog>(m, "CarmenLog", "A whole CARMEN log")
      .def_readonly("scans", &io::CarmenLog::scans)
      .def_readonly("odometry", &io::CarmenLog::odometry)
      .def_readonly("stats", &io::CarmenLog::stats)
      .def_readonly("warnings", &io::CarmenLog::warnings, "a cut-off end, damage skipped");
  m.def("read_carmen_log", &io::read_carmen_log, "path"_a, "options"_a = io::LogReadOptions{}, release_gil(),
        "Reads a whole CARMEN log (plain or gzip); InputError names the file, line and field of anything "
        "malformed.");
  m.def("write_carmen_log", &io::write_carmen_log, "path"_a, "scans"_a, "header"_a = "", release_gil(),
        "Writes scans as a corrected CARMEN log of FLASER messages (atomically).");

  py::class_<io::ScanSource>(m, "ScanSource", "Scans of a log or of the simulator, with the dataset's name")
      .def_readonly("name", &io::ScanSource::name, "the log's file name without .gz/.log/.clf, or 'sim-SEED'")
      .def_readonly("source", &io::ScanSource::source, "the spec it was loaded from")
      .def_readonly("scans", &io::ScanSource::scans)
      .def_readonly("T_base_laser", &io::ScanSource::T_base_laser,
                    "the laser's mount on the robot where the log says it (None otherwise); robot poses are "
                    "T_world_laser * T_base_laser^-1")
      .def_readonly("warnings", &io::ScanSource::warnings, "the reader's warnings: a cut-off end, damage skipped");
  m.def("is_simulator_spec", &io::is_simulator_spec, "spec"_a, "True for 'sim' and 'sim:SEED'.");
  m.def(
      "load_scan_source",
      [](const std::string& spec, const io::LogReadOptions& options) {
        io::ScanSource source;
        {
          py::gil_scoped_release unlocked;
          source = io::load_scan_source(spec, options);
        }
        // As the CLI prints them: a recording cut short or damage skipped is said, not only stored.
        for (const std::string& w : source.warnings)
          if (PyErr_WarnEx(PyExc_UserWarning, w.c_str(), 1) < 0) throw py::error_already_set();  // -W error
        return source;
      },
      "spec"_a, "options"_a = io::LogReadOptions{},
      "Loads a CARMEN log (.clf/.log, plain or .gz), a ROS 1 bag (.bag), a ROS 2 bag (.mcap, .db3, or a rosbag2 "
      "folder with metadata.yaml), or 'sim[:SEED]' (the built-in simulator); InputError carries the reader's "
      "message (file, line, field). The reader's warnings (a recording cut short, damage skipped) are issued as "
      "UserWarning and kept in .warnings.");
}

void define_database_records(py::module_& m) {
  py::enum_<io::DatasetKind>(m, "DatasetKind")
      .value("SUBMAPS", io::DatasetKind::kSubmaps)
      .value("DICTIONARY", io::DatasetKind::kDictionary);
  py::class_<io::DatasetSpec> spec(m, "DatasetSpec", "What a dataset is created with");
  spec.def_readwrite("name", &io::DatasetSpec::name, "unique within the database, non-empty")
      .def_readwrite("source", &io::DatasetSpec::source, "where the submaps came from")
      .def_readwrite("kind", &io::DatasetSpec::kind)
      .def_readwrite("config", &io::DatasetSpec::config, "the SubmapConfig the submaps were built with")
      .def_readwrite("scan_matched", &io::DatasetSpec::scan_matched, "poses from the front end, not the log");
  def_keyword_init(spec);
  py::class_<io::DatasetInfo>(m, "DatasetInfo", "A stored dataset with its counts")
      .def_readonly("id", &io::DatasetInfo::id)
      .def_readonly("spec", &io::DatasetInfo::spec)
      .def_property_readonly("name", [](const io::DatasetInfo& d) { return d.spec.name; })
      .def_readonly("created", &io::DatasetInfo::created, "UTC, ISO 8601")
      .def_readonly("submap_count", &io::DatasetInfo::submap_count)
      .def_readonly("mean_points", &io::DatasetInfo::mean_points)
      .def_readonly("first_map_id", &io::DatasetInfo::first_map_id)
      .def_readonly("last_map_id", &io::DatasetInfo::last_map_id)
      .def("__repr__", [](const io::DatasetInfo& d) {
        return "<partslam.DatasetInfo id=" + std::to_string(d.id) + " '" + d.spec.name +
               "' submaps=" + std::to_string(d.submap_count) + ">";
      });
  py::class_<io::MapLocation>(m, "MapLocation", "Where a map id lives")
      .def_readonly("map_id", &io::MapLocation::map_id)
      .def_readonly("dataset_id", &io::MapLocation::dataset_id)
      .def_readonly("dataset_name", &io::MapLocation::dataset_name)
      .def_readonly("index", &io::MapLocation::index, "position within its dataset, from 0");
  py::class_<io::DictionaryInfo>(m, "DictionaryInfo")
      .def_readonly("id", &io::DictionaryInfo::id)
      .def_readonly("name", &io::DictionaryInfo::name)
      .def_readonly("source", &io::DictionaryInfo::source)
      .def_readonly("resolution", &io::DictionaryInfo::resolution)
      .def_readonly("point_count", &io::DictionaryInfo::point_count)
      .def_readonly("created", &io::DictionaryInfo::created);
  py::class_<io::DescriptorRecord>(m, "DescriptorRecord", "One map's packed descriptor")
      .def(py::init<std::int64_t, PackedDescriptor>(), "map_id"_a, "descriptor"_a)
      .def_readonly("map_id", &io::DescriptorRecord::map_id)
      .def_readonly("descriptor", &io::DescriptorRecord::descriptor);
  py::class_<io::DescriptorSetInfo>(m, "DescriptorSetInfo", "Descriptors stored for one (dictionary, K)")
      .def_readonly("dictionary", &io::DescriptorSetInfo::dictionary)
      .def_readonly("k", &io::DescriptorSetInfo::k)
      .def_readonly("count", &io::DescriptorSetInfo::count)
      .def_readonly("mean_bits", &io::DescriptorSetInfo::mean_bits);
  py::class_<io::DatabaseSummary>(m, "DatabaseSummary")
      .def_readonly("schema_version", &io::DatabaseSummary::schema_version)
      .def_readonly("counts_kept", &io::DatabaseSummary::counts_kept)
      .def_readonly("datasets", &io::DatabaseSummary::datasets)
      .def_readonly("dictionaries", &io::DatabaseSummary::dictionaries)
      .def_readonly("descriptor_sets", &io::DatabaseSummary::descriptor_sets)
      .def_readonly("submap_count", &io::DatabaseSummary::submap_count)
      .def_readonly("point_count", &io::DatabaseSummary::point_count);
}

void define_database(py::module_& m) {
  using io::MapDatabase;
  py::class_<MapDatabase> db(
      m, "MapDatabase",
      "The SQLite map database (io/store/map_database.h). MapDatabase(path, mode) opens and checks "
      "it; it is closed when the object goes away.");
  py::enum_<MapDatabase::Mode>(db, "Mode")
      .value("READ_ONLY", MapDatabase::Mode::kReadOnly)
      .value("READ_WRITE", MapDatabase::Mode::kReadWrite)
      .value("CREATE", MapDatabase::Mode::kCreate);
  db.def(py::init(&MapDatabase::open), "path"_a, "mode"_a = MapDatabase::Mode::kReadOnly)
      .def_static("open", &MapDatabase::open, "path"_a, "mode"_a = MapDatabase::Mode::kReadOnly)
      .def_property_readonly("path", &MapDatabase::path)
      .def(
          "transaction", [](MapDatabase& d) { return TransactionScope(d); }, py::keep_alive<0, 1>(),
          "A context manager: the writes inside commit together, or not at all when it raises.")
      // datasets and submaps
      .def("add_dataset", &MapDatabase::add_dataset, "spec"_a)
      .def("add_submaps", &MapDatabase::add_submaps, "dataset_id"_a, "submaps"_a, "Returns their map ids.")
      .def("store_dataset", &MapDatabase::store_dataset, "spec"_a, "submaps"_a,
           "A dataset and its submaps in one transaction; returns the dataset id.")
      .def("remove_dataset", &MapDatabase::remove_dataset, "dataset_id"_a)
      .def("datasets", &MapDatabase::datasets)
      .def("dataset", &MapDatabase::dataset, "dataset_id"_a)
      .def("find_dataset", &MapDatabase::find_dataset, "name"_a, "The DatasetInfo named, or None.")
      .def("map_ids", &MapDatabase::map_ids, "dataset_id"_a)
      .def("load_submaps", &MapDatabase::load_submaps, "dataset_id"_a,
           "The submaps of a dataset in index order; Submap.id is the global map id.")
      .def("load_submap", &MapDatabase::load_submap, "map_id"_a)
      .def("locate", &MapDatabase::locate, "map_id"_a)
      // dictionaries
      .def("add_dictionary", &MapDatabase::add_dictionary, "dictionary"_a)
      .def("load_dictionary", &MapDatabase::load_dictionary, "name"_a)
      .def("dictionaries", &MapDatabase::dictionaries)
      .def("remove_dictionary", &MapDatabase::remove_dictionary, "name"_a)
      // descriptors
      .def("put_descriptor", &MapDatabase::put_descriptor, "map_id"_a, "dictionary"_a, "k"_a, "codec"_a,
           "descriptor"_a)
      .def("put_descriptors", &MapDatabase::put_descriptors, "dictionary"_a, "k"_a, "codec"_a, "records"_a,
           "Many descriptors of one (dictionary, K) in one transaction.")
      .def("descriptor_codec", &MapDatabase::descriptor_codec, "dictionary"_a, "k"_a,
           "The CodecConfig of the set, or None when it holds nothing.")
      .def("get_descriptor", &MapDatabase::get_descriptor, "map_id"_a, "dictionary"_a, "k"_a)
      .def("load_descriptors", &MapDatabase::load_descriptors, "dictionary"_a, "k"_a)
      .def("descriptor_sets", &MapDatabase::descriptor_sets)
      .def("summary", &MapDatabase::summary)
      .def("check_integrity", &MapDatabase::check_integrity);

  py::class_<TransactionScope>(m, "Transaction", "See MapDatabase.transaction()")
      .def("__enter__", [](TransactionScope& t) { t.enter(); })
      .def("__exit__", [](TransactionScope& t, const py::object& type, const py::object&, const py::object&) {
        t.exit(type);
        return false;
      });

  m.def("resolve_dictionary", &io::resolve_dictionary, "db"_a, "name"_a = "",
        "The dictionary named, or when name is empty the database's only one.");
  m.def(
      "load_descriptor_set",
      [](const MapDatabase& d, const std::string& dictionary, int k) {
        std::map<std::int64_t, std::vector<Part>> out;
        for (auto& [id, descriptor] : io::load_descriptor_set(d, dictionary, k))
          out[id] = std::move(descriptor.parts);
        return out;
      },
      "db"_a, "dictionary"_a, "k"_a,
      "Every stored descriptor of (dictionary, K), decoded: {map id: [Part]}.");
  m.def(
      "load_descriptor",
      [](const MapDatabase& d, const std::string& dictionary, int k, std::int64_t map_id) {
        std::optional<MapDescriptor> descriptor = io::load_descriptor(d, dictionary, k, map_id);
        return descriptor ? std::optional<std::vector<Part>>(std::move(descriptor->parts)) : std::nullopt;
      },
      "db"_a, "dictionary"_a, "k"_a, "map_id"_a,
      "One map's stored descriptor of (dictionary, K) decoded, or None.");
  m.def("query_list_parts", &io::query_list_parts, "db"_a, "dictionary"_a, "map_id"_a,
        "K of the longest hMM query list stored for the map's dictionary; 0 when there is none.");
}

}  // namespace

void define_io(py::module_& m) {
  define_logs(m);
  define_database_records(m);
  define_database(m);
}

}  // namespace partslam::python
