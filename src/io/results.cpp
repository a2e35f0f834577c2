#include "viaduct/io/results.hpp"
#include "viaduct/io/output_dir.hpp"

#include <cctype>
#include <charconv>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <algorithm>

#include <Eigen/Core>

#ifndef VIADUCT_TOML11_VERSION
#define VIADUCT_TOML11_VERSION "unknown"
#endif
#ifndef VIADUCT_VERSION
#define VIADUCT_VERSION "0.0.0"
#endif
#include "atomic_file.hpp"
#include "csv_cells.hpp"
#include "viaduct/core/thread_pool.hpp"
#include "viaduct/io/scenario.hpp"

namespace viaduct::io {

namespace {

using detail::AtomicFile;

using detail::csv_text;

}  // namespace

std::string version() { return VIADUCT_VERSION; }

void write_text_file(const std::string& path, const std::string& text) { detail::write_text_atomically(path, text); }

std::vector<std::pair<std::string, const Vector*>> history_columns(const study::RunResult& r) {
  std::vector<std::pair<std::string, const Vector*>> cols = {{"t_s", &r.t}};
  for (const auto& h : r.stations) {
    const std::string p = h.name + (h.on_deck ? "_" : "_rail_");
    cols.emplace_back(h.name + (h.on_deck ? "_disp_m" : "_rail_disp_m"), &h.disp);
    cols.emplace_back(p + "acc_mps2", &h.acc);
    if (h.acc_filt.size() > 0) cols.emplace_back(p + "acc_filt_mps2", &h.acc_filt);
    if (h.rail_disp.size() > 0) cols.emplace_back(h.name + "_rail_disp_m", &h.rail_disp);
  }
  for (const auto& e : r.effects) cols.emplace_back(e.name, &e.value);
  return cols;
}

void write_history_csv(const std::string& path, const study::RunResult& r) {
  AtomicFile f(path);
  const auto cols = history_columns(r);
  for (std::size_t j = 0; j < cols.size(); ++j) std::fprintf(f.get(), "%s%s", j ? "," : "", cols[j].first.c_str());
  std::fprintf(f.get(), "\n");
  for (Index k = 0; k < r.t.size(); ++k) {
    std::fprintf(f.get(), "%.6f", r.t[k]);
    for (std::size_t j = 1; j < cols.size(); ++j) std::fprintf(f.get(), ",%.9g", (*cols[j].second)[k]);
    std::fprintf(f.get(), "\n");
  }
  f.commit();
}

namespace {
// ",x" as printf's ",%.10g" writes it (std::to_chars with a precision is specified as printf in
// the C locale), without printf's format parsing: printf's formatting was 5 to 8 % of the sweep
// with 31 stations along a span (perf; load_effects.csv of 281 000 rows, docs/benchmarks.md).
// x's text into [b, b + 30), its end returned.
char* g10_text(char* b, double x) { return std::to_chars(b, b + 30, x, std::chars_format::general, 10).ptr; }

void add_g10(std::string& line, double x) {
  char b[32];
  line += ',';
  line.append(b, g10_text(b, x));
}

// A text cell as csv_text writes it, appended to line (no temporary string for a plain one).
void add_text(std::string& line, const std::string& s) {
  // A plain loop: find_first_of calls memchr over the three characters for each of s's (with its
  // memchr 1 % of the 31-station sweep on one thread in perf, three cells a row of load_effects.csv).
  bool plain = true;
  for (const char c : s) plain = plain && c != ',' && c != '"' && c != '\n';
  if (plain) line += s;
  else line += csv_text(s);
}

// The variant's columns of a sweep table: its label and, with variants, a KEY_factor column per
// varied key (the reference alone has none). header() writes the names, row() a row's cells.
class VariantColumns {
 public:
  explicit VariantColumns(const std::vector<study::Variant>& variants)
      : keys_(variants.size() < 2 ? std::vector<std::pair<std::string, double>>{} : variants.front().factors) {
    for (const auto& v : variants) by_label_[v.label] = &v;
  }
  void header(std::FILE* f) const { std::fputs(header_text().c_str(), f); }
  // header()'s cells as text.
  std::string header_text() const {
    std::string h = "variant";
    for (const auto& kf : keys_) h += "," + csv_text(kf.first + "_factor");
    return h;
  }
  void row(std::FILE* f, const std::string& variant, const char* file) const {
    std::string line;
    row_text(line, variant, file);
    std::fputs(line.c_str(), f);
  }
  // row()'s cells appended to line (add_g10 writes what printf's %.10g writes).
  void row_text(std::string& line, const std::string& variant, const char* file) const {
    add_text(line, variant);
    if (keys_.empty()) return;
    for (const auto& kf : factors_of(variant, file)) add_g10(line, kf.second);
  }
  const std::vector<std::pair<std::string, double>>& keys() const { return keys_; }
  // The factors of a row's variant on each varied key.
  const std::vector<std::pair<std::string, double>>& factors(const std::string& variant) const {
    return factors_of(variant, "envelope");
  }

 private:
  // The factors of a row's variant in table `file`; SolverError naming the file when unknown.
  const std::vector<std::pair<std::string, double>>& factors_of(const std::string& variant, const char* file) const {
    const auto it = by_label_.find(variant);
    if (it == by_label_.end() || it->second->factors.size() != keys_.size())
      throw SolverError(std::string(file) + ": row of an unknown variant '" + variant + "'");
    return it->second->factors;
  }
  std::vector<std::pair<std::string, double>> keys_;
  std::map<std::string, const study::Variant*> by_label_;
};
}  // namespace

void write_envelope_csv(const std::string& path, const std::vector<study::EnvelopeRow>& rows,
                        const std::vector<study::Variant>& variants) {
  const VariantColumns vc(variants);
  AtomicFile f(path);
  vc.header(f.get());
  std::fprintf(f.get(), ",train,speed_kmh,station,max_abs_acc_mps2,max_abs_disp_m\n");
  std::string line;
  for (const auto& r : rows) {
    vc.row(f.get(), r.variant, "envelope.csv");
    line = "," + csv_text(r.train);
    add_g10(line, r.speed * 3.6);
    line += "," + csv_text(r.station);
    add_g10(line, r.max_abs_acc);
    add_g10(line, r.max_abs_disp);
    line += '\n';
    std::fputs(line.c_str(), f.get());
  }
  f.commit();
}

namespace {
TableColumn text_column(const std::string& name) { return {name, TableColumn::Kind::text, {}, {}, {}}; }
TableColumn number_column(const std::string& name) { return {name, TableColumn::Kind::number, {}, {}, {}}; }

// A sweep table: variant, a KEY_factor column per varied key, then `rest`, which `fill` fills
// from each row (given the first of them).
template <class Row, class Fill>
std::vector<TableColumn> sweep_table(const std::vector<Row>& rows, const std::vector<study::Variant>& variants,
                                     std::vector<TableColumn> rest, Fill fill) {
  const VariantColumns vc(variants);
  std::vector<TableColumn> c = {text_column("variant")};
  for (const auto& kf : vc.keys()) c.push_back(number_column(kf.first + "_factor"));
  const std::size_t k = c.size();
  for (auto& col : rest) c.push_back(std::move(col));
  for (const auto& r : rows) {
    c[0].cells.push_back(r.variant);
    if (k > 1) {
      const auto& f = vc.factors(r.variant);
      for (std::size_t i = 0; i < f.size(); ++i) c[1 + i].values.push_back(f[i].second);
    }
    fill(r, &c[k]);
  }
  return c;
}
}  // namespace

std::vector<TableColumn> envelope_columns(const std::vector<study::EnvelopeRow>& rows,
                                         const std::vector<study::Variant>& variants) {
  return sweep_table(rows, variants,
                     {text_column("train"), number_column("speed_kmh"), text_column("station"), number_column("max_abs_acc_mps2"),
                      number_column("max_abs_disp_m")},
                     [](const study::EnvelopeRow& r, TableColumn* c) {
                       c[0].cells.push_back(r.train);
                       c[1].values.push_back(r.speed * 3.6);
                       c[2].cells.push_back(r.station);
                       c[3].values.push_back(r.max_abs_acc);
                       c[4].values.push_back(r.max_abs_disp);
                     });
}

std::vector<TableColumn> quantity_columns(const std::vector<study::QuantityRow>& rows, const std::vector<study::Variant>& variants) {
  std::vector<TableColumn> rest = {text_column("train"), number_column("speed_kmh"), text_column("quantity")};
  for (const char* n : {"max", "min", "max_abs", "quasi_static_max", "quasi_static_min", "phi_dyn"}) rest.push_back(number_column(n));
  return sweep_table(rows, variants, std::move(rest), [](const study::QuantityRow& r, TableColumn* c) {
    c[0].cells.push_back(r.train);
    c[1].values.push_back(r.speed * 3.6);
    c[2].cells.push_back(r.quantity);
    std::size_t j = 3;  // max, then min, max_abs, quasi_static_max, quasi_static_min, phi_dyn
    for (const double v : {r.dynamic.max, r.dynamic.min, r.dynamic.max_abs(), r.quasi_static.max, r.quasi_static.min, r.phi_dyn()})
      c[j++].values.push_back(v);
  });
}

std::vector<TableColumn> vehicle_envelope_columns(const std::vector<study::VehicleRow>& rows,
                                                 const std::vector<study::Variant>& variants) {
  std::vector<TableColumn> rest = {text_column("train"), number_column("speed_kmh"), number_column("min_contact_N"),
                                   number_column("max_contact_N"), number_column("max_unloading_ratio"),
                                   {"contact_lost", TableColumn::Kind::flag, {}, {}, {}}, number_column("max_airborne_s"),
                                   number_column("max_body_acc_mps2"), text_column("body"),
                                   number_column("max_floor_acc_mps2"), text_column("floor_body")};
  return sweep_table(rows, variants, std::move(rest), [](const study::VehicleRow& r, TableColumn* c) {
    const study::VehiclePeaks& p = r.peaks;
    c[0].cells.push_back(r.train);
    c[1].values.push_back(r.speed * 3.6);
    c[2].values.push_back(p.min_contact);
    c[3].values.push_back(p.max_contact);
    c[4].values.push_back(p.max_unloading_ratio);
    c[5].flags.push_back(p.contact_lost ? 1 : 0);
    c[6].values.push_back(p.max_airborne_s);
    c[7].values.push_back(p.max_body_acc);
    c[8].cells.push_back(p.body);
    c[9].values.push_back(p.max_floor_acc);
    c[10].cells.push_back(p.floor_body);
  });
}

void write_vehicle_envelope_csv(const std::string& path, const std::vector<study::VehicleRow>& rows,
                                const std::vector<study::Variant>& variants) {
  const VariantColumns vc(variants);
  AtomicFile f(path);
  vc.header(f.get());
  std::fprintf(f.get(), ",train,speed_kmh,min_contact_N,max_contact_N,max_unloading_ratio,contact_lost,max_airborne_s,max_body_acc_mps2,body,max_floor_acc_mps2,"
               "floor_body\n");
  for (const auto& r : rows) {
    vc.row(f.get(), r.variant, "vehicles.csv");
    const study::VehiclePeaks& p = r.peaks;
    std::fprintf(f.get(), ",%s,%.10g,%.10g,%.10g,%.10g,%s,%.10g,%.10g,%s,%.10g,%s\n", csv_text(r.train).c_str(), r.speed * 3.6,
                 p.min_contact, p.max_contact, p.max_unloading_ratio, p.contact_lost ? "true" : "false", p.max_airborne_s,
                 p.max_body_acc, csv_text(p.body).c_str(), p.max_floor_acc, csv_text(p.floor_body).c_str());
  }
  f.commit();
}

namespace {
// add_g10's text of the values met before, by their bits (a direct-mapped table): in
// load_effects.csv a case's speed repeats on each of its rows and a train's quasi-static extremes
// on each of its speeds, so of a row's seven numbers four are formatted once a block or a case
// (formatting was 0.14 s of the 31-station sweep's 1.6 s on one thread: docs/benchmarks.md).
class G10Memo {
 public:
  void add(std::string& line, double x) {
    std::uint64_t bits;
    std::memcpy(&bits, &x, sizeof bits);
    Entry& e = table_[((bits ^ (bits >> 31)) * 0x9E3779B97F4A7C15ull) >> (64 - kBits)];
    if (!e.used || e.bits != bits) {
      e.len = static_cast<unsigned char>(g10_text(e.text, x) - e.text);
      e.bits = bits, e.used = true;
    }
    line += ',';
    line.append(e.text, e.len);
  }

 private:
  static constexpr unsigned kBits = 9;  // 512 entries: a train's quasi-static extremes (2 a quantity) fit
  struct Entry {
    std::uint64_t bits = 0;
    bool used = false;
    unsigned char len = 0;
    char text[30];
  };
  Entry table_[std::size_t{1} << kBits];
};

// ",y" for y = p.max_abs() = max(hi, −lo) (hi, lo: p.max, p.min) as add_g10 writes it, from hi's
// and lo's texts (the cells just written, ",<hi>,<lo>" at the end of line): y is one of them bit
// for bit, and the text of −lo is lo's with its sign taken off or put on (to_chars writes −x as
// "-" and x's text).
void add_max_abs(std::string& line, const study::EffectPeak& p, std::size_t hi_at, std::size_t lo_at) {
  const double y = p.max_abs(), hi = p.max;
  std::uint64_t yb, hb;
  std::memcpy(&yb, &y, sizeof yb);
  std::memcpy(&hb, &hi, sizeof hb);
  char cell[48];  // the cells are to_chars' texts of ten digits: at most 17 characters
  std::size_t n = 0;
  if (yb == hb) {
    n = lo_at - hi_at;  // ",<hi>"
    line.copy(cell, n, hi_at);
  } else {
    const bool negative = line[lo_at + 1] == '-';
    cell[0] = ',';
    if (!negative) cell[1] = '-';
    const std::size_t from = lo_at + (negative ? 2 : 1), len = line.size() - from, at = negative ? 1 : 2;
    line.copy(cell + at, len, from);
    n = at + len;
  }
  line.append(cell, n);
}

// One row of load_effects.csv appended to text (memo: the block's formatted values).
void quantity_row(std::string& text, const VariantColumns& vc, const study::QuantityRow& r, G10Memo& memo) {
  vc.row_text(text, r.variant, "load_effects.csv");
  text += ',';
  add_text(text, r.train);
  memo.add(text, r.speed * 3.6);
  text += ',';
  add_text(text, r.quantity);
  const std::size_t hi_at = text.size();
  add_g10(text, r.dynamic.max);
  const std::size_t lo_at = text.size();
  add_g10(text, r.dynamic.min);
  add_max_abs(text, r.dynamic, hi_at, lo_at);
  memo.add(text, r.quasi_static.max);
  memo.add(text, r.quasi_static.min);
  // table_cell's text (an empty cell for NaN, else %.10g) without an ostringstream a row: 4.5 %
  // of the 31-station sweep on one thread (perf).
  if (const double phi = r.phi_dyn(); std::isnan(phi)) text += ',';
  else add_g10(text, phi);
  text += '\n';
}
}  // namespace

void write_quantities_csv(const std::string& path, const std::vector<study::QuantityRow>& rows,
                          const std::vector<study::Variant>& variants, int n_threads) {
  const VariantColumns vc(variants);
  AtomicFile f(path);
  // every byte through f.write: the manifest takes the checksum computed as it is written
  const std::string head =
      vc.header_text() + ",train,speed_kmh,quantity,max,min,max_abs,quasi_static_max,quasi_static_min,phi_dyn\n";
  f.write(head.data(), head.size());
  // Blocks of rows formatted on the threads and written in order, a wave of blocks at a time (the
  // text held at once bounded: about 7 MB on two threads). Formatting was most of what runs on one
  // core after the cases of a sweep with load effects (docs/benchmarks.md). A wave's text is
  // written (and hashed for the manifest, AtomicFile::write) by one of the threads while the others
  // format the next wave into the other set of buffers.
  constexpr std::size_t kBlock = 2048;
  const int nt = std::max(1, n_threads);
  const std::size_t n_blocks = (rows.size() + kBlock - 1) / kBlock, wave = 8 * static_cast<std::size_t>(nt);
  std::vector<std::string> text[2], error[2];
  for (int k = 0; k < 2; ++k) text[k].resize(std::min(wave, n_blocks)), error[k].resize(text[k].size());
  std::size_t n_prev = 0;  // blocks of the wave before, in text[1 - cur], to write
  int cur = 0;
  for (std::size_t b0 = 0; b0 < n_blocks; b0 += wave, cur = 1 - cur) {
    const std::size_t nb = std::min(wave, n_blocks - b0), extra = n_prev ? 1 : 0;
    std::vector<std::string>& tx = text[cur];
    std::vector<std::string>& er = error[cur];
    parallel_for(nb + extra, std::min(nt, static_cast<int>(nb + extra)), [&](std::size_t j, int) {
      if (extra && j == 0) {  // the wave before, in order (fwrite and the hash do not throw)
        for (std::size_t i = 0; i < n_prev; ++i) f.write(text[1 - cur][i].data(), text[1 - cur][i].size());
        return;
      }
      const std::size_t i = j - extra;
      // Each block's text is built in a string of the body's own: tx[i] and tx[i + 1] share a
      // cache line, and two threads appending to neighbours (each append writes the string's
      // size) made two threads format no faster than one (0.16 s against 0.14 s, 281 000 rows).
      std::string t;
      t.swap(tx[i]);  // its buffer, from two waves before
      t.clear();
      er[i].clear();
      try {
        const std::size_t a = (b0 + i) * kBlock, b = std::min(rows.size(), a + kBlock);
        auto memo = std::make_unique<G10Memo>();
        for (std::size_t k = a; k < b; ++k) quantity_row(t, vc, rows[k], *memo);
      } catch (const std::exception& e) {  // a body must not throw: rethrown below, in order
        er[i] = e.what();
      }
      tx[i].swap(t);
    });
    for (std::size_t i = 0; i < nb; ++i)
      if (!er[i].empty()) throw SolverError(er[i]);
    n_prev = nb;
  }
  for (std::size_t i = 0; i < n_prev; ++i) f.write(text[1 - cur][i].data(), text[1 - cur][i].size());
  f.commit();
}

void write_governing_csv(const std::string& path, const std::vector<study::GoverningRow>& rows) {
  AtomicFile f(path);
  std::fprintf(f.get(),
               "station,max_abs_acc_mps2,acc_variant,acc_train,acc_speed_kmh,max_abs_disp_m,disp_variant,disp_train,"
               "disp_speed_kmh\n");
  for (const auto& r : rows)
    std::fprintf(f.get(), "%s,%.10g,%s,%s,%.10g,%.10g,%s,%s,%.10g\n", csv_text(r.station).c_str(), r.acc.value,
                 csv_text(r.acc.variant).c_str(), csv_text(r.acc.train).c_str(), r.acc.speed * 3.6, r.disp.value,
                 csv_text(r.disp.variant).c_str(), csv_text(r.disp.train).c_str(), r.disp.speed * 3.6);
  f.commit();
}

void write_failures_csv(const std::string& path, const std::vector<study::CaseFailure>& failures) {
  AtomicFile f(path);
  std::fprintf(f.get(), "variant,train,speed_kmh,error\n");
  for (const auto& r : failures)
    std::fprintf(f.get(), "%s,%s,%.10g,%s\n", csv_text(r.variant).c_str(), csv_text(r.train).c_str(), r.speed * 3.6,
                 csv_text(r.message).c_str());
  f.commit();
}

void write_modes_csv(const std::string& path, const model::Modes& m, const model::Structure& structure,
                     const std::vector<study::ResolvedStation>& stations) {
  AtomicFile f(path);
  std::fprintf(f.get(), "mode,frequency_hz,kind,deck_mass_share,span,bending_order");
  for (const auto& s : stations) {
    if (s.has_deck) std::fprintf(f.get(), ",%s_deck", s.name.c_str());
    if (s.has_rail) std::fprintf(f.get(), ",%s_rail", s.name.c_str());
  }
  std::fprintf(f.get(), "\n");
  for (Index j = 0; j < m.frequency_hz.size(); ++j) {
    const Vector phi = m.shape.col(j);
    const model::ModeTag t = model::tag_mode(structure, phi);
    std::fprintf(f.get(), "%ld,%.10g,%s,%.4f", static_cast<long>(j + 1), m.frequency_hz[j], t.kind, t.deck_share);
    // The span and half-waves of the deck's bending; empty for a track mode (the deck barely moves).
    if (t.bending.span > 0) std::fprintf(f.get(), ",%d,%d", t.bending.span, t.bending.order);
    else std::fprintf(f.get(), ",,");
    for (const auto& s : stations) {
      if (s.has_deck) std::fprintf(f.get(), ",%.8g", s.deck.value(phi));
      if (s.has_rail) std::fprintf(f.get(), ",%.8g", s.rail.value(phi));
    }
    std::fprintf(f.get(), "\n");
  }
  f.commit();
}

void write_columns_csv(const std::string& path, const std::vector<std::string>& names,
                       const std::vector<Vector>& columns) {
  if (names.size() != columns.size() || columns.empty()) throw InputError("write_columns_csv: one name per column");
  for (const auto& c : columns)
    if (c.size() != columns.front().size()) throw InputError("write_columns_csv: columns differ in length");
  for (std::size_t j = 0; j < columns.size(); ++j)
    for (Index k = 0; k < columns[j].size(); ++k)
      if (!std::isfinite(columns[j][k]))
        throw SolverError("not writing " + path + ": column " + names[j] + " holds a non-finite value (row " + std::to_string(k + 1) +
                          ")");
  AtomicFile f(path);
  for (std::size_t j = 0; j < names.size(); ++j) std::fprintf(f.get(), "%s%s", j ? "," : "", csv_text(names[j]).c_str());
  std::fprintf(f.get(), "\n");
  for (Index k = 0; k < columns.front().size(); ++k) {
    for (std::size_t j = 0; j < columns.size(); ++j) std::fprintf(f.get(), "%s%.10g", j ? "," : "", columns[j][k]);
    std::fprintf(f.get(), "\n");
  }
  f.commit();
}

namespace {
bool is_non_finite_text(std::string s) {
  if (!s.empty() && (s[0] == '-' || s[0] == '+')) s.erase(0, 1);
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s == "nan" || s == "inf" || s == "infinity" || s.rfind("nan(", 0) == 0;
}
}  // namespace

std::string table_cell(double value, int significant) {
  return std::isnan(value) ? std::string() : format_number(value, significant);
}

void write_table_csv(const std::string& path, const std::vector<std::string>& header,
                     const std::vector<std::vector<std::string>>& rows) {
  // Cells come formatted: a number that came out non-finite is refused here, as by the other
  // writers (a computation failure, not a table to read back).
  for (std::size_t i = 0; i < rows.size(); ++i)
    for (std::size_t j = 0; j < rows[i].size() && j < header.size(); ++j)
      if (is_non_finite_text(rows[i][j]))
        throw SolverError("not writing " + path + ": column " + header[j] + " holds a non-finite value (row " +
                          std::to_string(i + 1) + ": " + rows[i][j] + ")");
  AtomicFile f(path);
  auto line = [&](const std::vector<std::string>& cells) {
    if (cells.size() != header.size()) throw InputError("write_table_csv: row width differs from the header");
    for (std::size_t j = 0; j < cells.size(); ++j) std::fprintf(f.get(), "%s%s", j ? "," : "", csv_text(cells[j]).c_str());
    std::fprintf(f.get(), "\n");
  };
  line(header);
  for (const auto& r : rows) line(r);
  f.commit();
}

void write_table_columns_csv(const std::string& path, const std::vector<TableColumn>& columns, int significant) {
  using Kind = TableColumn::Kind;
  auto length = [](const TableColumn& c) {
    return c.kind == Kind::text ? c.cells.size() : c.kind == Kind::number ? c.values.size() : c.flags.size();
  };
  const std::size_t n = columns.empty() ? 0 : length(columns.front());
  std::vector<std::string> header;
  std::vector<std::vector<std::string>> rows(n, std::vector<std::string>(columns.size()));
  for (std::size_t j = 0; j < columns.size(); ++j) {
    const TableColumn& c = columns[j];
    if (length(c) != n) throw InputError("write_table_columns_csv: column " + c.name + " differs in length");
    header.push_back(c.name);
    for (std::size_t i = 0; i < n; ++i)
      rows[i][j] = c.kind == Kind::text ? c.cells[i] : c.kind == Kind::number ? table_cell(c.values[i], significant)
                                                                              : (c.flags[i] ? "true" : "false");
  }
  write_table_csv(path, header, rows);
}

std::vector<std::pair<std::string, std::string>> settings_as_run(const study::RunSettings& s) {
  // TOML literals as the scenario writes them (Value::to_toml: numbers round-trip, strings escaped).
  auto num = [](double v) {
    Value x;
    x.type = ValueType::number;
    x.x = v;
    return x.to_toml();
  };
  auto str = [](const std::string& v) {
    Value x;
    x.type = ValueType::string;
    x.s = v;
    return x.to_toml();
  };
  auto yes = [](bool b) { return std::string(b ? "true" : "false"); };
  std::vector<std::pair<std::string, std::string>> out = {
      {"analysis.method", str(solve::method_name(s.method))},
      {"analysis.dt", num(s.dt)},
      {"analysis.superposition", str(s.superposition == study::Superposition::unit_response ? "unit-response" : "direct")}};
  switch (s.method) {
    case study::Method::newmark:
      out.insert(out.end(), {{"analysis.beta", num(s.newmark.beta)},
                             {"analysis.gamma", num(s.newmark.gamma)},
                             {"analysis.alpha", num(s.newmark.alpha)}});
      break;
    case study::Method::modal:
      out.insert(out.end(), {{"modal.n_modes", std::to_string(s.modal.n_modes)},
                             {"modal.max_frequency_hz", num(s.modal.max_frequency_hz)},
                             {"modal.static_correction", yes(s.modal.static_correction)},
                             {"modal.damping_vectors", std::to_string(s.modal.damping_vectors)}});
      break;
    case study::Method::ida:
      out.insert(out.end(), {{"ida.rtol", num(s.ida.rtol)},
                             {"ida.atol_disp_m", num(s.ida.atol_disp)},
                             {"ida.atol_vel_mps", num(s.ida.atol_vel)},
                             {"ida.max_order", std::to_string(s.ida.max_order)}});
      break;
  }
  const auto& c = s.filter.cheby;
  out.insert(out.end(),
             {{"analysis.free_vibration_s", num(s.free_vibration_s)},
              {"train.load_factor", num(s.load_factor)},
              {"filter.enabled", yes(s.filter.enabled)},
              {"filter.band", str(c.band == signal::BandType::lowpass    ? "lowpass"
                                  : c.band == signal::BandType::highpass ? "highpass"
                                                                         : "bandpass")},
              {"filter.order", std::to_string(c.order)},
              {"filter.ripple_db", num(c.ripple_db)},
              {"filter.low_hz", num(c.low_hz)},
              {"filter.high_hz", num(c.high_hz)}});
  if (s.vehicle.model != study::VehicleModel::forces) {
    // Moving forces keep their manifests as they were; vehicles say how they ran.
    const auto& v = s.vehicle;
    out.insert(out.end(), {{"train.vehicle", str(study::vehicle_model_name(v.model))},
                           {"train.contact", str(v.contact == study::ContactModel::rigid ? "rigid" : "hertz")},

                           {"train.contact_release", yes(v.release)},
                           {"train.end_transition_m", num(v.end_transition)}});
    if (v.contact_stiffness > 0.0) out.push_back({"train.contact_stiffness_N_m", num(v.contact_stiffness)});  // else Hertz's law
    const auto& r = s.irregularity;
    if (r.enabled())
      out.insert(out.end(), {{r.measured ? "irregularity.profile" : "irregularity.spectrum", str(r.measured ? r.measured_file : r.spectrum)},
                             {"irregularity.seed", std::to_string(r.seed)},
                             {"irregularity.run_in_m", num(r.run_in)},
                             {"irregularity.taper_m", num(r.taper)}});
  }
  return out;
}

void write_manifest(const std::string& path, const Manifest& m, const FlatScenario& flat) {
  write_manifest(path, m, &flat);
}

namespace {
// The scenario with every file it names as an absolute path: [scenario] is read again from the
// manifest's directory by viaduct replay (io::load_flat), where relative paths would not hold.
FlatScenario with_absolute_files(const FlatScenario& flat) {
  FlatScenario f = flat;
  auto absolute = [](std::string& p) {
    if (p.empty() || is_builtin_train(p)) return;
    std::error_code ec;
    const std::filesystem::path a = std::filesystem::absolute(p, ec);
    if (!ec) p = a.lexically_normal().string();
  };
  for (auto& [key, v] : f.values) {
    const bool file_key = key == "bridge.file" || key == "track.file" || key == "irregularity.profile" || key == "fit.modes" ||
                          (key.rfind("fit.records[", 0) == 0 && key.size() > 5 && key.compare(key.size() - 5, 5, ".file") == 0);
    if (key == "train.files")
      for (auto& t : v.ss) absolute(t);
    else if (file_key && v.type == ValueType::string)
      absolute(v.s);
  }
  return f;
}
}  // namespace

void write_manifest(const std::string& path, const Manifest& m, const FlatScenario* flat) {
  // Every file read: the scenario, the files its values came from (components), its trains, and
  // the command's own inputs; each once, in the order met.
  std::vector<std::string> files;
  auto add = [&](const std::string& f) {
    if (!f.empty() && f != "--set" && f != "default" && std::find(files.begin(), files.end(), f) == files.end())
      files.push_back(f);
  };
  if (flat) {
    add(flat->path);
    // A value a command set (assess's damping, filter and speeds: line 0 and a name that is no
    // file) names no input; a value read from a file has its line.
    for (const auto& kv : flat->values)
      if (kv.second.where.line > 0 || std::filesystem::is_regular_file(kv.second.where.file)) add(kv.second.where.file);
    if (flat->has("train.files"))
      for (const auto& t : flat->at("train.files").ss)
        if (!is_builtin_train(t)) add(t), add(coach_file_of(t));  // a train of coaches: its coach file too
    if (flat->has("irregularity.profile")) add(flat->at("irregularity.profile").s);
  }
  for (const auto& f : m.inputs) add(f);
  std::ostringstream out;
  const std::time_t now = std::chrono::system_clock::to_time_t(std::chrono::system_clock::now());
  char stamp[32];
  std::strftime(stamp, sizeof stamp, "%Y-%m-%dT%H:%M:%SZ", std::gmtime(&now));
  auto q = [](const std::string& s) {
    Value v;
    v.type = ValueType::string;
    v.s = s;
    return v.to_toml();
  };
  out << "# Written by viaduct; the [scenario] table holds every resolved key.\n";
  out << "[run]\n";
  out << "command = " << q(m.command) << "\n";
  if (!m.command_line.empty()) out << "command_line = " << q(m.command_line) << "\n";
  if (!m.command_line.empty()) {  // what viaduct replay runs again
    out << "positional = " << q(m.positional) << "\n";
    out << "arguments = [";
    for (std::size_t i = 0; i < m.arguments.size(); ++i) out << (i ? ", " : "") << q(m.arguments[i]);
    out << "]\n";
  }
  if (flat) {  // the keys of [scenario] that took their default (a replay lets them default again)
    out << "scenario_defaulted = [";
    bool first = true;
    for (const auto& k : flat->defaulted) out << (first ? "" : ", ") << q(k), first = false;
    out << "]\n";
  }
  if (flat) out << "scenario_file = " << q(flat->path) << "\n";
  out << "finished_utc = " << q(stamp) << "\n";
  out << "wall_s = " << m.wall_s << "\n";
  for (const auto& [k, v] : m.extra) out << k << " = " << v << "\n";
  if (!m.warnings.empty()) {
    out << "warnings = [";
    for (std::size_t i = 0; i < m.warnings.size(); ++i) out << (i ? ", " : "") << q(m.warnings[i]);
    out << "]\n";
  }
  out << "\n[versions]\n";
  out << "viaduct = " << q(version()) << "\n";
  out << "git_commit = " << q(git_commit()) << "\n";
  out << "eigen = " << q(std::to_string(EIGEN_WORLD_VERSION) + "." + std::to_string(EIGEN_MAJOR_VERSION) + "." +
                         std::to_string(EIGEN_MINOR_VERSION))
      << "\n";
  out << "toml11 = " << q(VIADUCT_TOML11_VERSION) << "\n";
#ifdef __VERSION__
  out << "compiler = " << q(__VERSION__) << "\n";
#endif
  for (const auto& [k, v] : m.versions) out << k << " = " << q(v) << "\n";
  if (!m.as_run.empty()) {
    out << "\n[analysis_as_run]\n";
    for (const auto& [k, v] : m.as_run) out << q(k) << " = " << v << "\n";
  }
  for (const auto& f : files) {
    std::string sum;
    std::error_code ec;
    if (std::filesystem::is_directory(f, ec)) {
      sum = "directory";
    } else {
      try {
        sum = sha256_file(f);
      } catch (const InputError&) {
        sum = "unreadable";
      }
    }
    out << "\n[[inputs]]\nfile = " << q(f) << "\nsha256 = " << q(sum) << "\n";
  }
  // The files this run wrote beside the manifest, with their checksums (output_dir.hpp): the
  // manifest is written last, so a directory whose files do not match it holds two runs.
  const std::filesystem::path mdir = std::filesystem::path(path).has_parent_path() ? std::filesystem::path(path).parent_path() : ".";
  for (const auto& f : outputs_written(mdir.string())) {
    if (std::filesystem::path(f).filename() == std::filesystem::path(path).filename()) continue;
    // The checksum computed as the file was written, else read from the file.
    std::error_code ec;
    if (!std::filesystem::is_regular_file(f, ec)) continue;  // removed since
    std::string sum = output_checksum(f);
    try {
      if (sum.empty()) sum = sha256_file(f);
    } catch (const InputError&) {
      continue;  // removed since (a later file of the same run replaced it)
    }
    out << "\n[[outputs]]\nfile = " << q(std::filesystem::path(f).filename().string()) << "\nsha256 = " << q(sum) << "\n";
  }
  if (flat) out << "\n[scenario]\n" << resolved_toml(with_absolute_files(*flat));
  detail::write_text_atomically(path, out.str());
}

}  // namespace viaduct::io
