#include "io/dicom/dicom_header.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <set>

#include <fmt/format.h>
#include <gdcmReader.h>
#include <glm/geometric.hpp>

#include "intermix/error.hpp"
#include "io/dicom/dicom_structure.hpp"
#include "io/dicom/dicom_tags.hpp"
#include "io/dicom/siemens_csa.hpp"
#include "io/streams/header_text.hpp"
#include "io/streams/input_file.hpp"

namespace imx::detail {

namespace {

constexpr int kMaxFrames = 1 << 16;           // far more than any scanner writes into one file
constexpr uintmax_t kMaxMetaBytes = 1 << 16;  // the file meta group is a few hundred bytes

bool positive(double v) {
  return v > 0.0;
}
bool non_zero(double v) {
  return v != 0.0;
}

// A tag of three numbers (ImagePositionPatient); nullopt when absent.
std::optional<glm::dvec3> vec3_of(const gdcm::DataSet& ds, uint16_t g, uint16_t e,
                                  const std::string& file, const char* name) {
  auto v = used_numbers(ds, g, e, file, name, "three finite numbers expected");
  if (!v) return std::nullopt;
  if (v->size() < 3)
    throw Error(
        unusable_message(file, name, g, e, *tag_text(ds, g, e), "three finite numbers expected"));
  return glm::dvec3((*v)[0], (*v)[1], (*v)[2]);
}

// Reads ImageOrientationPatient into the frame: two unit vectors (to within half their length,
// as scanners round them), else the tag is refused as unusable.
void read_orientation(const gdcm::DataSet& ds, DicomFrame& f, const std::string& file) {
  const char* why = "two direction vectors of six finite numbers, each of length about 1";
  auto v = used_numbers(ds, 0x0020, 0x0037, file, "ImageOrientationPatient", why);
  if (!v) return;
  glm::dvec3 r, c;
  double lr = 0.0, lc = 0.0;
  if (v->size() >= 6) {
    r = glm::dvec3((*v)[0], (*v)[1], (*v)[2]);
    c = glm::dvec3((*v)[3], (*v)[4], (*v)[5]);
    lr = glm::length(r);
    lc = glm::length(c);
  }
  if (!(lr > 0.5 && lr < 1.5 && lc > 0.5 && lc < 1.5))
    throw Error(unusable_message(file, "ImageOrientationPatient", 0x0020, 0x0037,
                                 *tag_text(ds, 0x0020, 0x0037), why));
  f.row_direction = r / lr;
  f.column_direction = c / lc;
}

void read_spacing(const gdcm::DataSet& ds, DicomFrame& f, const std::string& file) {
  const char* why = "two finite positive numbers expected";
  auto v = used_numbers(ds, 0x0028, 0x0030, file, "PixelSpacing", why, positive);
  if (!v) return;
  if (v->size() < 2)
    throw Error(
        unusable_message(file, "PixelSpacing", 0x0028, 0x0030, *tag_text(ds, 0x0028, 0x0030), why));
  f.pixel_spacing = glm::dvec2((*v)[0], (*v)[1]);
}

void read_rescale(const gdcm::DataSet& ds, DicomFrame& f, const std::string& file) {
  if (auto s = used_numbers(ds, 0x0028, 0x1053, file, "RescaleSlope",
                            "a finite non-zero number expected", non_zero))
    f.slope = s->front();
  if (auto i =
          used_numbers(ds, 0x0028, 0x1052, file, "RescaleIntercept", "a finite number expected"))
    f.intercept = i->front();
}

void read_window(const gdcm::DataSet& ds, DicomFrame& f) {
  auto c = tag_number(ds, 0x0028, 0x1050), w = tag_number(ds, 0x0028, 0x1051);
  if (c && w && *w > 0.0) f.window = glm::dvec2(*c, *w);
}

// The data set of the first item of sequence (g,e) inside `ds`, kept alive by `holder`.
const gdcm::DataSet* first_item(const gdcm::DataSet& ds, uint16_t g, uint16_t e,
                                gdcm::SmartPointer<gdcm::SequenceOfItems>& holder) {
  holder = tag_sequence(ds, g, e);
  if (!holder || holder->GetNumberOfItems() < 1) return nullptr;
  return &holder->GetItem(1).GetNestedDataSet();
}

// A tag's number as an int: values beyond any real count are clamped (a cast would be undefined).
int clamped_int(double v) {
  return static_cast<int>(std::clamp(v, -1e9, 1e9));
}

// DiffusionBValue (0018,9087) and DiffusionGradientOrientation (0018,9089), directly in `ds` or
// in its DiffusionGradientDirectionSequence (0018,9076).
void read_standard_diffusion(const gdcm::DataSet& ds, DicomFrame& f) {
  if (std::vector<double> b = tag_fd(ds, 0x0018, 0x9087); b.size() == 1 && b[0] >= 0.0)
    f.b_value = b[0];
  auto gradient = [&](const gdcm::DataSet& g) {
    if (std::vector<double> v = tag_fd(g, 0x0018, 0x9089); v.size() == 3)
      f.gradient = glm::dvec3(v[0], v[1], v[2]);
  };
  gradient(ds);
  // DiffusionDirectionality (0018,9075) ISOTROPIC: a trace image of an enhanced file.
  if (tag_text(ds, 0x0018, 0x9075).value_or("") == "ISOTROPIC" && f.b_value.value_or(0.0) > 0.0)
    f.derived_diffusion = true;
  gdcm::SmartPointer<gdcm::SequenceOfItems> hold;
  if (const gdcm::DataSet* s = first_item(ds, 0x0018, 0x9076, hold)) gradient(*s);
}

// GE's (0019,xxBB-BD) gradient is not in patient space but along the image's phase, frequency
// and slice axes. dcm2niix (geCorrectBvecs) swaps the first two for row phase encoding and
// mirrors the axes its slice class (sagittal, coronal, axial: the normal's largest component)
// lists; expressed along the row, column and normal (row x column) of the image, that gives the
// direction it writes, which is turned here into patient space. A length between 0.03 and 0.97
// scales the b-value by its square, as GE's scaled multi-shell tensors mean (and dcm2niix reads).
void ge_gradient_to_patient(const gdcm::DataSet& ds, glm::dvec3 v, DicomFrame& f,
                            std::vector<std::string>& notes) {
  const double length = glm::length(v);
  if (length <= 1e-6) {
    f.gradient = glm::dvec3(0.0);
    // dcm2niix reads a b-value without a direction (a trace, or a b = 0 misnamed) as b = 0.
    if (f.b_value && *f.b_value > 0.0) {
      notes.push_back(
          "GE diffusion: images with b > 0 but no direction (trace, or b = 0) are read as b = 0, "
          "as dcm2niix reads them");
      f.b_value = 0.0;
    }
    return;
  }
  if (!f.row_direction || !f.column_direction) return;  // cannot be placed: left unknown
  if (length > 0.03 && length < 0.97 && f.b_value) {
    f.b_value = *f.b_value * length * length;
    v /= length;
  }
  std::string phase = tag_text(ds, 0x0018, 0x1312).value_or("");
  if (phase != "ROW" && phase != "COL") {
    notes.push_back(
        "GE diffusion directions: no InPlanePhaseEncodingDirection (0018,1312) of ROW or COL "
        "says which image axis (0019,xxBB) follows; read as COL, GE's usual");
    phase = "COL";
  }
  if (phase == "ROW") v = glm::dvec3(v.y, -v.x, v.z);
  const glm::dvec3 r = *f.row_direction, c = *f.column_direction;
  const glm::dvec3 n = glm::normalize(glm::cross(r, c));
  const glm::dvec3 a = glm::abs(n);
  glm::dvec3 mirror(1.0, 1.0, -1.0);  // axial
  if (a.x > a.y && a.x > a.z)
    mirror = glm::dvec3(-1.0, -1.0, 1.0);  // sagittal
  else if (a.y > a.x && a.y > a.z)
    mirror = glm::dvec3(1.0, -1.0, -1.0);  // coronal
  v = -(v * mirror);
  f.gradient = r * v.x + c * v.y + n * v.z;
}

// The vendors' private diffusion tags of classic (single-frame) files, each read only under its
// own private creator: Siemens (0019,xx0C/0E), GE (0043,xx39 b-value; 0019,xxBB-BD gradient),
// Philips (2001,xx03 b-value; 2005,xxB0-B2 gradient).
void read_private_diffusion(const gdcm::DataSet& ds, DicomFrame& f,
                            std::vector<std::string>& notes) {
  if (auto b = private_block(ds, 0x0019, "SIEMENS MR HEADER")) {
    if (auto v = tag_number(ds, 0x0019, *b | 0x0C); v && *v >= 0.0) f.b_value = v;
    if (std::vector<double> g = tag_fd(ds, 0x0019, *b | 0x0E); g.size() == 3)
      f.gradient = glm::dvec3(g[0], g[1], g[2]);
  }
  if (auto b = private_block(ds, 0x0043, "GEMS_PARM_01")) {
    // The first value of slop_int_6; some versions add 1e9 (a flag) to it.
    if (auto v = tag_number(ds, 0x0043, *b | 0x39); v && *v >= 0.0) f.b_value = std::fmod(*v, 1e9);
  }
  if (auto b = private_block(ds, 0x0019, "GEMS_ACQU_01")) {
    auto x = tag_number(ds, 0x0019, *b | 0xBB), y = tag_number(ds, 0x0019, *b | 0xBC),
         z = tag_number(ds, 0x0019, *b | 0xBD);
    if (x && y && z) ge_gradient_to_patient(ds, glm::dvec3(*x, *y, *z), f, notes);
  }
  if (auto b = private_block(ds, 0x2001, "Philips Imaging DD 001")) {
    if (std::vector<double> v = tag_fl(ds, 0x2001, *b | 0x03); v.size() == 1 && v[0] >= 0.0)
      f.b_value = v[0];
    // Diffusion direction 'I': the isotropic (trace) image Philips derives from the others.
    if (tag_text(ds, 0x2001, *b | 0x04).value_or("") == "I" && f.b_value.value_or(0.0) > 0.0)
      f.derived_diffusion = true;
  }
  if (auto b = private_block(ds, 0x2005, "Philips MR Imaging DD 001")) {
    std::vector<double> x = tag_fl(ds, 0x2005, *b | 0xB0), y = tag_fl(ds, 0x2005, *b | 0xB1),
                        z = tag_fl(ds, 0x2005, *b | 0xB2);
    if (x.size() == 1 && y.size() == 1 && z.size() == 1) f.gradient = glm::dvec3(x[0], y[0], z[0]);
  }
}

// The top-level tags that tell volumes apart, for every frame of the file.
void read_volume_keys(const gdcm::DataSet& ds, const std::string& image_type, DicomFrame& f,
                      std::vector<std::string>& notes) {
  if (auto t = tag_number(ds, 0x0020, 0x0100)) f.temporal_position = clamped_int(*t);
  if (auto t = tag_number(ds, 0x0018, 0x1060)) f.trigger_time_ms = t;
  if (auto e = tag_number(ds, 0x0018, 0x0086)) f.echo_number = clamped_int(*e);
  if (auto e = tag_number(ds, 0x0018, 0x0081)) f.echo_time_ms = e;
  if (auto tr = tag_number(ds, 0x0018, 0x0080); tr && *tr > 0.0) f.repetition_time_ms = tr;
  if (auto tm = tag_text(ds, 0x0008, 0x0032)) f.acquisition_time_s = parse_dicom_time(*tm);
  if (!f.acquisition_time_s)
    if (auto dt = tag_text(ds, 0x0008, 0x002a); dt && dt->size() > 8)
      f.acquisition_time_s = parse_dicom_time(dt->substr(8));
  read_private_diffusion(ds, f, notes);
  read_standard_diffusion(ds, f);
  // ImageType's third value names the complex component of MR images (M, P, R, I).
  std::vector<std::string> parts;
  for (size_t at = 0;;) {
    size_t cut = image_type.find('\\', at);
    parts.push_back(image_type.substr(at, cut - at));
    if (cut == std::string::npos) break;
    at = cut + 1;
  }
  // ADC, trace and isotropic images computed from the diffusion-weighted ones (dcm2niix keeps
  // them out of the DWI).
  if (!parts.empty() && parts[0] == "DERIVED")
    for (const std::string& p : parts)
      if (p == "ADC" || p == "TRACEW" || p == "TRACE" || p == "ISOTROPIC" || p == "FA")
        f.derived_diffusion = true;
  if (parts.size() >= 3 &&
      (parts[2] == "M" || parts[2] == "P" || parts[2] == "R" || parts[2] == "I"))
    f.complex_component = parts[2];
  if (auto c = tag_text(ds, 0x0008, 0x9208)) f.complex_component = c->substr(0, 1);
}

// Applies one functional-groups item (shared or per-frame) to a frame.
void apply_functional_groups(const gdcm::DataSet& group, DicomFrame& f, const std::string& file) {
  gdcm::SmartPointer<gdcm::SequenceOfItems> hold;
  if (const gdcm::DataSet* s = first_item(group, 0x0020, 0x9113, hold))  // PlanePosition
    if (auto p = vec3_of(*s, 0x0020, 0x0032, file, "ImagePositionPatient")) f.position = p;
  if (const gdcm::DataSet* s = first_item(group, 0x0020, 0x9116, hold))  // PlaneOrientation
    read_orientation(*s, f, file);
  if (const gdcm::DataSet* s = first_item(group, 0x0028, 0x9110, hold))  // PixelMeasures
    read_spacing(*s, f, file);
  if (const gdcm::DataSet* s = first_item(group, 0x0028, 0x9145, hold))  // PixelValueTransf.
    read_rescale(*s, f, file);
  if (const gdcm::DataSet* s = first_item(group, 0x0028, 0x9132, hold))  // FrameVOILUT
    read_window(*s, f);
  if (const gdcm::DataSet* s = first_item(group, 0x0020, 0x9111, hold)) {  // FrameContent
    if (std::vector<uint32_t> d = tag_ul(*s, 0x0020, 0x9157); !d.empty()) f.dimension_index = d;
    if (std::vector<uint32_t> t = tag_ul(*s, 0x0020, 0x9128); t.size() == 1)
      f.temporal_position = static_cast<int>(std::min<uint32_t>(t[0], 1u << 30));
    if (auto dt = tag_text(*s, 0x0018, 0x9074); dt && dt->size() > 8)  // FrameAcquisitionDateTime
      if (auto tm = parse_dicom_time(dt->substr(8))) f.acquisition_time_s = tm;
  }
  if (const gdcm::DataSet* s = first_item(group, 0x0018, 0x9118, hold))  // CardiacSynchronization
    if (std::vector<double> t = tag_fd(*s, 0x0020, 0x9153); t.size() == 1) f.trigger_time_ms = t[0];
  if (const gdcm::DataSet* s = first_item(group, 0x0018, 0x9112, hold))  // MRTimingAndRelated
    if (auto tr = tag_number(*s, 0x0018, 0x0080); tr && *tr > 0.0) f.repetition_time_ms = tr;
  if (const gdcm::DataSet* s = first_item(group, 0x0018, 0x9114, hold))  // MREcho
    if (std::vector<double> t = tag_fd(*s, 0x0018, 0x9082); t.size() == 1) f.echo_time_ms = t[0];
  if (const gdcm::DataSet* s = first_item(group, 0x0018, 0x9117, hold))  // MRDiffusion
    read_standard_diffusion(*s, f);
  if (const gdcm::DataSet* s = first_item(group, 0x0018, 0x9226, hold))  // MRImageFrameType
    if (auto c = tag_text(*s, 0x0008, 0x9208)) f.complex_component = c->substr(0, 1);
}

void read_suv_tags(const gdcm::DataSet& ds, DicomSuvTags& t) {
  t.units = tag_text(ds, 0x0054, 0x1001);
  t.decay_correction = tag_text(ds, 0x0054, 0x1102);
  t.weight_kg = tag_number(ds, 0x0010, 0x1030);
  if (auto tm = tag_text(ds, 0x0008, 0x0031)) t.series_time_s = parse_dicom_time(*tm);
  if (auto tm = tag_text(ds, 0x0008, 0x0032)) t.acquisition_time_s = parse_dicom_time(*tm);
  gdcm::SmartPointer<gdcm::SequenceOfItems> hold;
  if (const gdcm::DataSet* r = first_item(ds, 0x0054, 0x0016, hold)) {
    t.has_radiopharmaceutical = true;
    t.total_dose_bq = tag_number(*r, 0x0018, 0x1074);
    t.half_life_s = tag_number(*r, 0x0018, 0x1075);
    if (auto tm = tag_text(*r, 0x0018, 0x1072)) t.start_time_s = parse_dicom_time(*tm);
    if (!t.start_time_s)  // RadiopharmaceuticalStartDateTime: YYYYMMDDHHMMSS.frac
      if (auto dt = tag_text(*r, 0x0018, 0x1078); dt && dt->size() >= 10)
        t.start_time_s = parse_dicom_time(dt->substr(8));
  }
}

// GE's research EPI "epi_pepolar" says in user data 12 (0019,xxB3) which volumes it acquired with
// the phase encoding reversed, whose rows dcm2niix mirrors back: 1 all of them; 2 the odd and 3
// the even TemporalPositionIdentifiers (0020,0100), where dcm2niix then converts the odd and the
// even time points as two series (the `polarity_part`, 1 and 2, keeps them apart here too).
// Without a temporal position dcm2niix mirrors none and keeps one series: so does this.
void read_ge_polarity(const gdcm::DataSet& ds, DicomFileHeader& h) {
  auto b = private_block(ds, 0x0019, "GEMS_ACQU_01");
  if (!b) return;
  std::string name = tag_text(ds, 0x0019, *b | 0x9C).value_or("") + " " +
                     tag_text(ds, 0x0019, *b | 0x9E).value_or("");
  std::transform(name.begin(), name.end(), name.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (name.find("epi_pepolar") == std::string::npos) return;
  const double user_data_12 = tag_number(ds, 0x0019, *b | 0xB3).value_or(0.0);
  if (user_data_12 == 1.0) h.mirror_rows = true;
  if (user_data_12 != 2.0 && user_data_12 != 3.0) return;
  const std::optional<int> time =
      h.frames.empty() ? std::nullopt : h.frames.front().temporal_position;
  if (!time) {
    h.notes.push_back(
        "GE epi_pepolar with alternating phase encoding (user data 12 (0019,10B3)) but no "
        "TemporalPositionIdentifier (0020,0100): read as stored, as dcm2niix reads it");
    return;
  }
  const bool odd = *time % 2 != 0;
  h.polarity_part = odd ? 1 : 2;
  h.mirror_rows = (user_data_12 == 2.0) == odd;
  h.notes.push_back(fmt::format(
      "GE epi_pepolar with alternating phase encoding: the {} time points, one polarity, are this "
      "series; the other polarity is series part {}",
      odd ? "odd" : "even", odd ? 2 : 1));
}

// A Siemens mosaic: the tiles of one volume side by side in one image, as many per row as per
// column (the smallest square that holds them). Each tile becomes a frame placed where it lies:
// ImagePositionPatient names the mosaic's corner, so the first tile's is moved by half the
// difference in size; the tiles then step along the CSA SliceNormalVector (which may point
// against row x column) by the slice spacing.
void split_into_tiles(const gdcm::DataSet& ds, DicomFileHeader& h) {
  const std::string what = h.file.string();
  std::optional<int> tiles;
  std::optional<glm::dvec3> normal;
  const auto csa = parse_csa_header(tag_bytes(ds, 0x0029, 0x1010));
  if (auto b = private_block(ds, 0x0019, "SIEMENS MR HEADER"))
    if (auto n = tag_us(ds, 0x0019, *b | 0x0A)) tiles = *n;
  if (auto n = csa_numbers(csa, "NumberOfImagesInMosaic"); n && !tiles)
    tiles = static_cast<int>(std::clamp((*n)[0], 0.0, 65535.0));
  if (auto n = csa_numbers(csa, "SliceNormalVector"); n && n->size() == 3)
    normal = glm::dvec3((*n)[0], (*n)[1], (*n)[2]);
  if (!tiles)
    throw Error(fmt::format(
        "{}: a Siemens mosaic (ImageType MOSAIC) without NumberOfImagesInMosaic (0019,100A) or a "
        "CSA image header: its tiles cannot be told apart",
        what));
  const int per_row = static_cast<int>(std::ceil(std::sqrt(static_cast<double>(*tiles))));
  if (*tiles < 1 || h.frame_count != 1 || h.rows % per_row != 0 || h.columns % per_row != 0)
    throw Error(fmt::format(
        "{}: a mosaic of {} images does not tile its {}x{} pixels ({} per row) in one frame", what,
        *tiles, h.columns, h.rows, per_row));
  DicomFrame base = h.frames.front();
  if (!base.position || !base.row_direction || !base.pixel_spacing)
    throw Error(fmt::format(
        "{}: a mosaic without ImagePositionPatient, ImageOrientationPatient or PixelSpacing "
        "cannot be placed",
        what));
  const glm::dvec3 cross = glm::normalize(glm::cross(*base.row_direction, *base.column_direction));
  if (!normal || !(glm::length(*normal) > 0.5)) normal = cross;  // Siemens' usual
  *normal = glm::normalize(*normal);
  if (std::abs(std::abs(glm::dot(*normal, cross)) - 1.0) > 1e-3)
    throw Error(
        fmt::format("{}: the mosaic's SliceNormalVector is not normal to its slices", what));
  h.rows /= per_row;
  h.columns /= per_row;
  h.mosaic_tiles = *tiles;
  h.frame_count = *tiles;
  const double shift_columns = (h.stored_columns - h.columns) / 2.0;
  const double shift_rows = (h.stored_rows - h.rows) / 2.0;
  const glm::dvec3 first = *base.position +
                           *base.row_direction * (base.pixel_spacing->y * shift_columns) +
                           *base.column_direction * (base.pixel_spacing->x * shift_rows);
  const double step = required_slice_spacing(h, "a mosaic's tiles");
  h.frames.clear();
  for (int t = 0; t < *tiles; ++t) {
    DicomFrame f = base;
    f.frame = t;
    f.position = first + *normal * (step * t);
    h.frames.push_back(f);
  }
}

// "a DICOM file without an image: no Rows (0028,0010)", saying which of the two is absent or 0.
std::string without_image_reason(std::optional<int> rows, std::optional<int> columns) {
  std::vector<std::string> faults;
  for (auto [value, name] : {std::pair{rows, "Rows (0028,0010)"}, {columns, "Columns (0028,0011)"}})
    if (!value)
      faults.push_back(fmt::format("no {}", name));
    else if (*value == 0)
      faults.push_back(fmt::format("{} is 0", name));
  std::string reason = "a DICOM file without an image: ";
  for (size_t i = 0; i < faults.size(); ++i) reason += (i > 0 ? " and " : "") + faults[i];
  return reason;
}

}  // namespace

bool looks_like_dicom(const std::filesystem::path& file) {
  std::ifstream in = try_open_input_stream(file);
  char head[132] = {};
  in.read(head, sizeof head);
  const std::streamsize got = in.gcount();
  if (got == 132 && std::memcmp(head + 128, "DICM", 4) == 0) return true;
  // A bare data set (ACR-NEMA style) starts with a group 0008 element, little endian.
  return got >= 8 && head[0] == 0x08 && head[1] == 0x00;
}

std::string file_meta_fault(const std::filesystem::path& file) {
  const std::string cut = "a DICOM file that cannot be read (truncated or corrupt): ";
  std::error_code ec;
  const uintmax_t size = std::filesystem::file_size(file, ec);
  if (ec) return fmt::format("cannot read its size: {}", ec.message());
  std::ifstream in = try_open_input_stream(file);
  std::vector<unsigned char> head(static_cast<size_t>(std::min<uintmax_t>(size, kMaxMetaBytes)));
  in.read(reinterpret_cast<char*>(head.data()), static_cast<std::streamsize>(head.size()));
  if (in.gcount() != static_cast<std::streamsize>(head.size()))
    return fmt::format("cannot read its first {} bytes", head.size());
  if (head.size() < 132 || std::memcmp(head.data() + 128, "DICM", 4) != 0) {
    if (head.size() >= 8 && head[0] == 0x08 && head[1] == 0x00) return "";  // no meta group
    return cut + "no DICM preamble and no data set";
  }
  // GDCM asserts (aborts) on a meta element that is a sequence, of undefined length or cut
  // short: each must be explicit VR little endian, with a known VR, inside the file.
  static const char* const kLongVrs[] = {"OB", "OD", "OF", "OL", "OV", "OW",
                                         "UC", "UN", "UR", "UT", "SV", "UV"};
  static const char* const kShortVrs[] = {"AE", "AS", "AT", "CS", "DA", "DS", "DT",
                                          "FL", "FD", "IS", "LO", "LT", "PN", "SH",
                                          "SL", "SS", "ST", "TM", "UI", "UL", "US"};
  size_t at = 132;
  int elements = 0;
  std::optional<std::string> syntax;
  while (at + 8 <= head.size()) {
    const unsigned group = head[at] | (head[at + 1] << 8);
    const unsigned element = head[at + 2] | (head[at + 3] << 8);
    if (group != 0x0002) break;
    const std::string tag = tag_name(0x0002, static_cast<uint16_t>(element));
    if (elements == 0 && element != 0x0000)
      return cut + fmt::format(
                       "the file meta information starts with {}, not its group length "
                       "(0002,0000)",
                       tag);
    const char vr[3] = {static_cast<char>(head[at + 4]), static_cast<char>(head[at + 5]), 0};
    auto in_list = [&](const auto& list) {
      return std::any_of(std::begin(list), std::end(list),
                         [&](const char* v) { return std::strcmp(v, vr) == 0; });
    };
    uint64_t length = 0;
    size_t value = 0;
    if (in_list(kShortVrs)) {
      length = head[at + 6] | (head[at + 7] << 8);
      value = at + 8;
    } else if (in_list(kLongVrs)) {
      if (at + 12 > head.size()) return cut + "the file meta information is cut short";
      length = static_cast<uint64_t>(head[at + 8]) | (static_cast<uint64_t>(head[at + 9]) << 8) |
               (static_cast<uint64_t>(head[at + 10]) << 16) |
               (static_cast<uint64_t>(head[at + 11]) << 24);
      if (length == 0xffffffffu)
        return cut + fmt::format("file meta element {} has an undefined length", tag);
      value = at + 12;
    } else {
      return cut +
             fmt::format("file meta element {} has no valid VR (a sequence or not a VR)", tag);
    }
    if (elements == 0 && (std::strcmp(vr, "UL") != 0 || length != 4))
      return cut + "the group length (0002,0000) is not a 4-byte UL";
    if (value + length > head.size())
      return cut + fmt::format("file meta element {} runs past the end of the file", tag);
    if (element == 0x0010) {
      syntax.emplace(reinterpret_cast<const char*>(head.data() + value),
                     static_cast<size_t>(length));
      while (!syntax->empty() && (syntax->back() == '\0' || syntax->back() == ' '))
        syntax->pop_back();
    }
    at = value + static_cast<size_t>(length);
    ++elements;
  }
  if (elements == 0 || at + 8 > head.size())
    return cut + "the file ends after its file meta information, with no data set";
  // GDCM cannot read on without knowing how the data set is encoded (and says so on stderr).
  if (!syntax) return "no TransferSyntaxUID (0002,0010) in its file meta information";
  const gdcm::TransferSyntax::TSType type = gdcm::TransferSyntax::GetTSType(syntax->c_str());
  if (type == gdcm::TransferSyntax::TS_END)
    return fmt::format("unknown or unsupported transfer syntax '{}' (0002,0010)", shown(*syntax));
  if (type == gdcm::TransferSyntax::DeflatedExplicitVRLittleEndian)
    return fmt::format("the transfer syntax {} (0002,0010), a deflated data set, is not supported",
                       *syntax);
  return "";
}

double required_slice_spacing(const DicomFileHeader& h, const char* use) {
  if (h.slice_spacing) return *h.slice_spacing;
  if (!h.slice_spacing_fault.empty())
    throw Error(fmt::format("{}; it is needed to place {}", h.slice_spacing_fault, use));
  throw Error(fmt::format(
      "{}: no SpacingBetweenSlices (0018,0088) or SliceThickness (0018,0050) to place {}",
      h.file.string(), use));
}

// The value length of the element whose value starts at byte `value_at` of `file`: the four
// bytes before it, in every encoding of the pixel data element (implicit VR, or explicit OB/OW
// with two reserved bytes). 0xFFFFFFFF is the undefined length of encapsulated data.
std::optional<uint32_t> value_length_before(const std::filesystem::path& file, size_t value_at,
                                            bool big_endian) {
  if (value_at < 8) return std::nullopt;
  std::ifstream in = try_open_input_stream(file);
  in.seekg(static_cast<std::streamoff>(value_at - 4));
  unsigned char b[4];
  if (!in.read(reinterpret_cast<char*>(b), 4)) return std::nullopt;
  return big_endian ? (uint32_t{b[0]} << 24 | uint32_t{b[1]} << 16 | uint32_t{b[2]} << 8 | b[3])
                    : (uint32_t{b[3]} << 24 | uint32_t{b[2]} << 16 | uint32_t{b[1]} << 8 | b[0]);
}

// Refuses pixel data whose form or length contradicts the header: encapsulated fragments under
// a native transfer syntax or a plain value under a compressed one (a relabelled file), and
// native data that is not exactly Rows x Columns x frames x samples x BitsAllocated bits (plus
// the one pad byte of an odd length): GDCM pads short data with zeros and reads only the first
// bytes of long data, and either would load the wrong pixels without a word.
void check_pixel_data(const DicomFileHeader& h) {
  const std::string what = h.file.string();
  const gdcm::TransferSyntax::TSType type =
      gdcm::TransferSyntax::GetTSType(h.transfer_syntax.c_str());
  if (type == gdcm::TransferSyntax::TS_END)
    throw Error(fmt::format("{}: unknown or unsupported transfer syntax '{}' (0002,0010)", what,
                            h.transfer_syntax));
  const gdcm::TransferSyntax ts(type);
  if (ts.IsEncoded() || !h.has_pixel_data) return;
  const bool undefined = !h.pixel_length;
  if (ts.IsEncapsulated() && !undefined)
    throw Error(fmt::format(
        "{}: the transfer syntax {} says the pixel data is compressed, but it is a plain value "
        "of {} bytes",
        what, transfer_syntax_label(h.transfer_syntax), *h.pixel_length));
  if (!ts.IsEncapsulated() && undefined)
    throw Error(
        fmt::format("{}: the transfer syntax {} says the pixel data is not compressed, but it is "
                    "encapsulated (compressed fragments)",
                    what, transfer_syntax_label(h.transfer_syntax)));
  if (ts.IsEncapsulated()) return;
  const uint64_t bits = static_cast<uint64_t>(h.stored_rows) * h.stored_columns *
                        static_cast<uint64_t>(h.stored_frames) *
                        static_cast<uint64_t>(std::max(h.samples_per_pixel, 1)) *
                        static_cast<uint64_t>(std::max(h.bits_allocated, 0));
  const uint64_t needed = (bits + 7) / 8;
  const uint64_t found = *h.pixel_length;
  if (found < needed)
    throw Error(fmt::format("{}: truncated pixel data: {} of {} bytes", what, found, needed));
  if (found > needed + needed % 2)
    throw Error(fmt::format(
        "{}: the pixel data holds {} bytes, but Rows x Columns x NumberOfFrames x SamplesPerPixel "
        "x BitsAllocated ({} x {} x {} x {} x {} bits) give {}: a wrong NumberOfFrames or size?",
        what, found, h.stored_rows, h.stored_columns, h.stored_frames, h.samples_per_pixel,
        h.bits_allocated, needed));
}

namespace {

// SpacingBetweenSlices, else SliceThickness: the first usable one. Where neither is and one
// is present, its fault is kept for whoever needs a slice spacing (one slice, a mosaic, a
// legacy multi-frame file); a stack of slices places them by their positions instead.
void read_slice_spacing(const gdcm::DataSet& ds, DicomFileHeader& h) {
  const std::string what = h.file.string();
  for (uint16_t element : {uint16_t{0x0088}, uint16_t{0x0050}}) {
    const char* name = element == 0x0088 ? "SpacingBetweenSlices" : "SliceThickness";
    try {
      if (auto v = used_numbers(ds, 0x0018, element, what, name,
                                "a finite positive number expected", positive)) {
        h.slice_spacing = v->front();
        h.slice_spacing_fault.clear();
        break;
      }
    } catch (const Error& e) {
      if (h.slice_spacing_fault.empty()) h.slice_spacing_fault = e.what();
    }
  }
}

// Every frame's placement and values: the top-level tags, then the shared and per-frame
// functional groups over them; a legacy multi-frame file's frames stacked along the normal.
void read_frames(const gdcm::DataSet& ds, const std::string& image_type, DicomFileHeader& h) {
  const std::string what = h.file.string();
  DicomFrame base;
  base.file = h.file;
  base.position = vec3_of(ds, 0x0020, 0x0032, what, "ImagePositionPatient");
  read_orientation(ds, base, what);
  read_spacing(ds, base, what);
  read_rescale(ds, base, what);
  read_window(ds, base);
  base.instance_number = h.instance_number;
  read_volume_keys(ds, image_type, base, h.notes);
  gdcm::SmartPointer<gdcm::SequenceOfItems> shared_hold;
  if (const gdcm::DataSet* shared = first_item(ds, 0x5200, 0x9229, shared_hold))
    apply_functional_groups(*shared, base, what);
  gdcm::SmartPointer<gdcm::SequenceOfItems> per_frame = tag_sequence(ds, 0x5200, 0x9230);
  for (int f = 0; f < h.frame_count; ++f) {
    DicomFrame frame = base;
    frame.frame = f;
    if (per_frame && static_cast<size_t>(f) < per_frame->GetNumberOfItems())
      apply_functional_groups(per_frame->GetItem(static_cast<size_t>(f) + 1).GetNestedDataSet(),
                              frame, what);
    h.frames.push_back(std::move(frame));
  }
  // A legacy multi-frame file (no per-frame groups) stacks its frames along the normal.
  if (!per_frame && h.frame_count > 1 && base.position && base.row_direction) {
    const glm::dvec3 normal = glm::cross(*base.row_direction, *base.column_direction);
    const double step =
        required_slice_spacing(h, "the frames of a multi-frame file without per-frame positions");
    for (DicomFrame& f : h.frames) f.position = *base.position + normal * (f.frame * step);
  }
}

}  // namespace

std::optional<DicomFileHeader> read_dicom_header(const std::filesystem::path& file,
                                                 std::string* not_image) {
  quiet_gdcm();
  // A file that cannot be opened (a permission) says why, not that it is no DICOM file.
  open_input_unrecorded(file);
  if (!looks_like_dicom(file)) {
    if (not_image != nullptr) *not_image = "not a DICOM file (no DICM preamble)";
    return std::nullopt;
  }
  const std::string broken = fmt::format(
      "{}: a DICOM file that cannot be read (truncated or "
      "corrupt)",
      file.string());
  if (std::string fault = file_meta_fault(file); !fault.empty())
    throw Error(fmt::format("{}: {}", file.string(), fault));
  if (std::string fault = check_dicom_structure(file); !fault.empty())
    throw Error(fmt::format("{}: {}", broken, fault));
  const InputFd fd = open_input(file);  // GDCM opens by name: the checked file's name
  gdcm::Reader reader;
  reader.SetFileName(path_of_open(fd, file).c_str());
  // The pixel data is skipped, not read: the stream then stops just after its element header.
  std::set<gdcm::Tag> skip{gdcm::Tag(0x7fe0, 0x0010)};
  bool ok = false;
  size_t pixel_offset = static_cast<size_t>(-1);
  try {
    ok = reader.ReadUpToTag(gdcm::Tag(0x7fe0, 0x0010), skip);
    pixel_offset = reader.GetStreamCurrentPosition();
  } catch (...) {
    ok = false;
  }
  if (!ok) throw Error(broken);
  const gdcm::DataSet& ds = reader.GetFile().GetDataSet();
  std::error_code size_ec;
  const uintmax_t file_size = std::filesystem::file_size(file, size_ec);

  const std::string& what = file.string();
  DicomFileHeader h;
  h.file = file;
  auto rows = tag_us(ds, 0x0028, 0x0010), columns = tag_us(ds, 0x0028, 0x0011);
  if (!rows || !columns || *rows == 0 || *columns == 0) {
    if (not_image != nullptr) *not_image = without_image_reason(rows, columns);
    return std::nullopt;
  }
  h.rows = *rows;
  h.columns = *columns;
  h.series_uid = tag_text(ds, 0x0020, 0x000e).value_or("");
  h.sop_uid = tag_text(ds, 0x0008, 0x0018).value_or("");
  h.description = tag_text(ds, 0x0008, 0x103e).value_or("");
  h.modality = tag_text(ds, 0x0008, 0x0060).value_or("");
  h.photometric = tag_text(ds, 0x0028, 0x0004).value_or("");
  h.rescale_type = tag_text(ds, 0x0028, 0x1054).value_or("");
  h.series_number =
      static_cast<int>(std::clamp(tag_number(ds, 0x0020, 0x0011).value_or(0.0), -1e9, 1e9));
  h.instance_number =
      static_cast<int>(std::clamp(tag_number(ds, 0x0020, 0x0013).value_or(0.0), -1e9, 1e9));
  std::string image_type = tag_text(ds, 0x0008, 0x0008).value_or("");
  std::transform(image_type.begin(), image_type.end(), image_type.begin(),
                 [](unsigned char c) { return static_cast<char>(std::toupper(c)); });
  h.localizer = image_type.find("LOCALIZER") != std::string::npos;
  if (!size_ec && pixel_offset < file_size) {
    h.has_pixel_data = true;
    h.pixel_bytes = file_size - pixel_offset;
  }
  h.transfer_syntax =
      tag_text(reader.GetFile().GetHeader(), 0x0002, 0x0010).value_or("1.2.840.10008.1.2");
  if (h.has_pixel_data) {
    const auto length = value_length_before(
        file, pixel_offset, h.transfer_syntax == "1.2.840.10008.1.2.2");  // explicit VR big endian
    if (length && *length != 0xffffffffu) h.pixel_length = *length;
  }
  h.bits_allocated = tag_us(ds, 0x0028, 0x0100).value_or(0);
  h.bits_stored = tag_us(ds, 0x0028, 0x0101).value_or(h.bits_allocated);
  h.high_bit = tag_us(ds, 0x0028, 0x0102).value_or(h.bits_stored - 1);
  h.pixel_representation = tag_us(ds, 0x0028, 0x0103).value_or(0);
  h.samples_per_pixel = tag_us(ds, 0x0028, 0x0002).value_or(1);
  h.planar_configuration = tag_us(ds, 0x0028, 0x0006).value_or(0);
  read_slice_spacing(ds, h);
  const auto whole = [](double v) { return v >= 1.0 && v <= kMaxFrames && v == std::floor(v); };
  double frames = 1.0;
  if (auto n = used_numbers(ds, 0x0028, 0x0008, what, "NumberOfFrames",
                            "a whole number of frames from 1 to 65536 expected")) {
    frames = n->front();
    if (n->size() != 1 || !whole(frames))
      throw Error(unusable_message(what, "NumberOfFrames", 0x0028, 0x0008,
                                   *tag_text(ds, 0x0028, 0x0008),
                                   "a whole number of frames from 1 to 65536 expected"));
  }
  h.frame_count = static_cast<int>(frames);
  h.stored_rows = h.rows;
  h.stored_columns = h.columns;
  h.stored_frames = h.frame_count;

  read_frames(ds, image_type, h);
  if (image_type.find("MOSAIC") != std::string::npos) split_into_tiles(ds, h);
  read_ge_polarity(ds, h);
  read_suv_tags(ds, h.suv);
  check_pixel_data(h);
  return h;
}

}  // namespace imx::detail
