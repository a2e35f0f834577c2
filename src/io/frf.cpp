#include "viaduct/io/frf.hpp"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <sstream>

#include "viaduct/core/error.hpp"
#include "atomic_file.hpp"
#include "csv_cells.hpp"

namespace viaduct::io {

namespace {

using detail::split_csv;

// Rows of numbers after a header; '#' lines skipped. Errors name file, line and column.
struct Table {
  std::vector<std::string> header;
  std::vector<std::vector<double>> rows;
  std::vector<int> line_of_row;
};

Table read_table(const std::string& path) {
  const detail::TextTable text = detail::read_text_table(path, /*quoted=*/false);
  Table t;
  t.header = text.header;
  for (std::size_t r = 0; r < text.rows.size(); ++r) {
    const auto& cells = text.rows[r];
    std::vector<double> row;
    for (std::size_t c = 0; c < cells.size(); ++c) {
      char* end = nullptr;
      const double v = std::strtod(cells[c].c_str(), &end);
      if (cells[c].empty() || end == cells[c].c_str() || *end != '\0' || !std::isfinite(v))
        throw InputError(path + ":" + std::to_string(text.lines[r]) + ": column '" + t.header[c] + "': '" + cells[c] +
                         "' is not a finite number");
      row.push_back(v);
    }
    t.rows.push_back(std::move(row));
    t.line_of_row.push_back(text.lines[r]);
  }
  if (t.rows.empty()) throw InputError(path + ": no data rows");
  return t;
}

std::string fmt(double v) {
  char b[40];
  std::snprintf(b, sizeof b, "%.10g", v);
  return b;
}

}  // namespace

void write_frf_csv(const std::string& path, const ident::Frf& frf) {
  frf.check(path);
  std::ostringstream out;
  const bool coh = frf.coherence.size() != 0;
  out << "frequency_hz";
  for (Index c = 0; c < frf.n_responses(); ++c) {
    const std::string& n = frf.responses[static_cast<std::size_t>(c)];
    const std::string u = ident::unit_of_quantity(frf.quantity[static_cast<std::size_t>(c)]) + "_per_" + frf.force_unit;
    out << "," << n << "_re_" << u << "," << n << "_im_" << u << "," << n << "_mag_" << u << "," << n << "_phase_deg";
    if (coh) out << "," << n << "_coherence";
  }
  out << "\n";
  for (Index k = 0; k < frf.frequency_hz.size(); ++k) {
    out << fmt(frf.frequency_hz[k]);
    for (Index c = 0; c < frf.n_responses(); ++c) {
      const auto h = frf.h(k, c);
      out << "," << fmt(h.real()) << "," << fmt(h.imag()) << "," << fmt(std::abs(h)) << ","
          << fmt(std::arg(h) * 180.0 / M_PI);
      if (coh) out << "," << fmt(frf.coherence(k, c));
    }
    out << "\n";
  }
  detail::write_text_atomically(path, out.str());
}

ident::Frf read_frf_csv(const std::string& path) {
  const Table t = read_table(path);
  if (t.header[0] != "frequency_hz") throw InputError(path + ": the first column must be frequency_hz, not '" + t.header[0] + "'");
  ident::Frf frf;
  struct Cols {
    int re = -1, im = -1, coh = -1;
    ident::FrfQuantity q = ident::FrfQuantity::accelerance;
  };
  std::vector<std::string> order;
  std::map<std::string, Cols> cols;
  std::string force_unit;
  for (std::size_t c = 1; c < t.header.size(); ++c) {
    const std::string& h = t.header[c];
    for (const char* part : {"_re_", "_im_"}) {
      const auto p = h.rfind(part);
      if (p == std::string::npos) continue;
      const std::string name = h.substr(0, p), rest = h.substr(p + 4);
      const auto per = rest.find("_per_");
      if (per == std::string::npos) throw InputError(path + ": column '" + h + "' lacks '_per_<force unit>'");
      const std::string fu = rest.substr(per + 5);
      if (fu != "N" && fu != "kN") throw InputError(path + ": column '" + h + "': force unit must be N or kN");
      if (!force_unit.empty() && fu != force_unit) throw InputError(path + ": columns mix force units");
      force_unit = fu;
      if (!cols.count(name)) order.push_back(name);
      Cols& cc = cols[name];
      try {
        cc.q = ident::quantity_of_unit(rest.substr(0, per));
      } catch (const InputError& e) {
        throw InputError(path + ": column '" + h + "': " + e.what());
      }
      (std::string(part) == "_re_" ? cc.re : cc.im) = static_cast<int>(c);
      break;
    }
    const std::string suffix = "_coherence";
    if (h.size() > suffix.size() && h.compare(h.size() - suffix.size(), suffix.size(), suffix) == 0) {
      const std::string name = h.substr(0, h.size() - suffix.size());
      if (!cols.count(name)) order.push_back(name);
      cols[name].coh = static_cast<int>(c);
    }
  }
  if (order.empty()) throw InputError(path + ": no '<name>_re_<unit>_per_N' column: not an FRF file");
  bool any_coh = false, all_coh = true;
  for (const auto& n : order) {
    const Cols& cc = cols[n];
    if (cc.re < 0 || cc.im < 0) throw InputError(path + ": response '" + n + "' needs both _re_ and _im_ columns");
    any_coh = any_coh || cc.coh >= 0;
    all_coh = all_coh && cc.coh >= 0;
  }
  const Index nf = static_cast<Index>(t.rows.size()), nr = static_cast<Index>(order.size());
  frf.force_unit = force_unit;
  frf.frequency_hz.resize(nf);
  frf.h.resize(nf, nr);
  if (any_coh && all_coh) frf.coherence.resize(nf, nr);
  for (Index k = 0; k < nf; ++k) {
    const auto& row = t.rows[static_cast<std::size_t>(k)];
    frf.frequency_hz[k] = row[0];
    if (k > 0 && !(row[0] > frf.frequency_hz[k - 1]))
      throw InputError(path + ":" + std::to_string(t.line_of_row[static_cast<std::size_t>(k)]) + ": frequencies must increase");
    for (Index c = 0; c < nr; ++c) {
      const Cols& cc = cols[order[static_cast<std::size_t>(c)]];
      frf.h(k, c) = {row[static_cast<std::size_t>(cc.re)], row[static_cast<std::size_t>(cc.im)]};
      if (frf.coherence.size()) frf.coherence(k, c) = row[static_cast<std::size_t>(cc.coh)];
    }
  }
  for (const auto& n : order) {
    frf.responses.push_back(n);
    frf.quantity.push_back(cols[n].q);
  }
  frf.check(path);
  return frf;
}

void write_steps_csv(const std::string& path, const std::vector<ident::SineStep>& steps) {
  std::ostringstream out;
  out << "t_start_s,t_end_s,frequency_hz\n";
  for (const auto& s : steps) out << fmt(s.t_start_s) << "," << fmt(s.t_end_s) << "," << fmt(s.frequency_hz) << "\n";
  detail::write_text_atomically(path, out.str());
}

std::vector<ident::SineStep> read_steps_csv(const std::string& path) {
  const Table t = read_table(path);
  if (t.header != std::vector<std::string>{"t_start_s", "t_end_s", "frequency_hz"})
    throw InputError(path + ": the header must be t_start_s,t_end_s,frequency_hz");
  std::vector<ident::SineStep> s;
  for (std::size_t k = 0; k < t.rows.size(); ++k) {
    const auto& r = t.rows[k];
    const std::string where = path + ":" + std::to_string(t.line_of_row[k]) + ": ";
    if (!(r[1] > r[0])) throw InputError(where + "t_end_s must exceed t_start_s");
    if (!(r[2] > 0.0)) throw InputError(where + "frequency_hz must be > 0");
    s.push_back({r[0], r[1], r[2]});
  }
  return s;
}

namespace {
std::string fmt_rate(double v) {
  char b[48];
  std::snprintf(b, sizeof b, "%.8g", v);
  return b;
}
}  // namespace

FrfInputs frf_inputs(const Record& rec, const std::string& record_path, const Record* force_record,
                     const std::string& force, const std::vector<std::string>& responses) {
  const Record& frec = force_record ? *force_record : rec;
  if (force_record) {
    if (std::abs(frec.fs_hz - rec.fs_hz) > 1e-9 * rec.fs_hz)
      throw InputError("mismatched sampling rates: force record at " + fmt_rate(frec.fs_hz) + " Hz, responses at " +
                       fmt_rate(rec.fs_hz) + " Hz (resample one with viaduct resample)");
    if (std::abs(frec.t0_s - rec.t0_s) > 0.5 / rec.fs_hz || frec.n_samples() != rec.n_samples())
      throw InputError("the force record and the response record do not cover the same samples (start or length differ)");
  }
  FrfInputs in;
  const std::size_t fc = frec.channel(force);
  std::vector<std::size_t> used_r;
  if (!responses.empty())
    for (const auto& c : responses) used_r.push_back(rec.channel(c));
  if (!force_record) {  // one record: the longest piece where the channels used all have values
    std::vector<std::size_t> used = used_r;
    used.push_back(fc);
    if (responses.empty())
      for (std::size_t c = 0; c < rec.channels.size(); ++c)
        if (rec.units[c] == "m" || rec.units[c] == "mps" || rec.units[c] == "mps2") used.push_back(c);
    const Record cut = valid_span(rec, used, "frf", &in.notes);
    if (!in.notes.empty()) {
      FrfInputs out = frf_inputs(cut, record_path, nullptr, force, responses);
      out.notes = in.notes;
      return out;
    }
  } else {
    for (const auto& [r, cs] : {std::pair<const Record*, std::vector<std::size_t>>{&frec, {fc}}, {&rec, used_r}})
      for (const std::size_t c : cs)
        for (const auto& [a, b] : missing_runs(*r, c))
          throw InputError("frf: channel " + r->channels[c] + " has no value from " + format_number(r->t0_s + static_cast<double>(a) / r->fs_hz, 8) +
                           " to " + format_number(r->t0_s + static_cast<double>(b - 1) / r->fs_hz, 8) +
                           " s: with a separate force record both must hold every sample (cut both to a common span first)");
  }
  in.force_channel = frec.channels[fc];
  in.force_unit = frec.units[fc];
  if (in.force_unit != "N" && in.force_unit != "kN") throw InputError("force channel '" + in.force_channel + "' must be in N or kN");
  std::vector<std::size_t> chans;
  if (!responses.empty()) {
    for (const auto& c : responses) chans.push_back(rec.channel(c));
  } else {
    for (std::size_t c = 0; c < rec.channels.size(); ++c)
      if (rec.units[c] == "m" || rec.units[c] == "mps" || rec.units[c] == "mps2") chans.push_back(c);
  }
  if (chans.empty()) throw InputError("no response channel (m, mps or mps2) in " + record_path);
  in.force = frec.data.col(static_cast<Index>(fc));
  in.responses.resize(rec.n_samples(), static_cast<Index>(chans.size()));
  for (std::size_t j = 0; j < chans.size(); ++j) {
    in.responses.col(static_cast<Index>(j)) = rec.data.col(static_cast<Index>(chans[j]));
    in.response_channels.push_back(rec.channels[chans[j]]);
    in.response_units.push_back(rec.units[chans[j]]);
  }
  in.fs_hz = rec.fs_hz;
  in.t0_s = rec.t0_s;
  return in;
}

void label_frf(ident::Frf& frf, const FrfInputs& in) {
  frf.force_unit = in.force_unit;
  frf.responses.clear();
  frf.quantity.clear();
  for (std::size_t c = 0; c < in.response_channels.size(); ++c) {
    const std::string& channel = in.response_channels[c];
    const std::string& unit = in.response_units[c];
    std::string name = channel.substr(0, channel.size() - unit.size() - 1);
    for (const char* tag : {"_acc", "_vel", "_disp"}) {
      const std::string t = tag;
      if (name.size() > t.size() && name.compare(name.size() - t.size(), t.size(), t) == 0) {
        name.resize(name.size() - t.size());
        break;
      }
    }
    frf.responses.push_back(name);
    frf.quantity.push_back(ident::quantity_of_unit(unit));
  }
}

}  // namespace viaduct::io
