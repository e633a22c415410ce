// The DICOM pixel codecs alone: the input is one compressed stream and the image it claims to
// hold. Byte 0 picks the transfer syntax (RLE, JPEG baseline, JPEG lossless, JPEG-LS, JPEG 2000),
// byte 1 the bits (8 or 16), bytes 2 and 3 the rows and columns (1 to 64); the rest is the
// stream, wrapped as the one fragment of an encapsulated slice and read as read_dicom reads it
// (decoded in a process of its own). Seeds (fuzz/corpus/fuzz_codec) are an 8x8 gradient
// compressed by GDCM in each syntax.
#include <cstring>
#include <exception>

#include <gdcmDataElement.h>
#include <gdcmFragment.h>
#include <gdcmSequenceOfFragments.h>
#include <gdcmWriter.h>

#include "harness.hpp"
#include "intermix/dicom.hpp"

namespace {

constexpr gdcm::TransferSyntax::TSType kSyntaxes[] = {
    gdcm::TransferSyntax::RLELossless, gdcm::TransferSyntax::JPEGBaselineProcess1,
    gdcm::TransferSyntax::JPEGLosslessProcess14_1, gdcm::TransferSyntax::JPEGLSLossless,
    gdcm::TransferSyntax::JPEG2000Lossless};

void put(gdcm::DataSet& ds, uint16_t g, uint16_t e, gdcm::VR vr, std::string v) {
  if (v.size() % 2 != 0) v.push_back(vr == gdcm::VR::UI ? '\0' : ' ');
  gdcm::DataElement de(gdcm::Tag(g, e));
  de.SetVR(vr);
  de.SetByteValue(v.data(), static_cast<uint32_t>(v.size()));
  ds.Replace(de);
}

void put_us(gdcm::DataSet& ds, uint16_t g, uint16_t e, uint16_t v) {
  gdcm::DataElement de(gdcm::Tag(g, e));
  de.SetVR(gdcm::VR::US);
  de.SetByteValue(reinterpret_cast<const char*>(&v), 2);
  ds.Replace(de);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace imx::fuzz;
  if (size < 5) return 0;
  const auto syntax = kSyntaxes[data[0] % std::size(kSyntaxes)];
  const uint16_t bits = data[1] & 1 ? 16 : 8;
  const uint16_t rows = 1 + data[2] % 64, columns = 1 + data[3] % 64;
  std::string stream(reinterpret_cast<const char*>(data + 4), size - 4);
  if (stream.size() % 2 != 0) stream.push_back('\0');

  gdcm::Writer w;
  gdcm::DataSet& ds = w.GetFile().GetDataSet();
  put(ds, 0x0008, 0x0016, gdcm::VR::UI, "1.2.840.10008.5.1.4.1.1.2");
  put(ds, 0x0008, 0x0018, gdcm::VR::UI, "1.2.3.4.5");
  put(ds, 0x0008, 0x0060, gdcm::VR::CS, "CT");
  put(ds, 0x0020, 0x000e, gdcm::VR::UI, "1.2.3.4");
  put(ds, 0x0020, 0x0032, gdcm::VR::DS, "0\\0\\0");
  put(ds, 0x0020, 0x0037, gdcm::VR::DS, "1\\0\\0\\0\\1\\0");
  put(ds, 0x0028, 0x0004, gdcm::VR::CS, "MONOCHROME2");
  put(ds, 0x0028, 0x0030, gdcm::VR::DS, "1\\1");
  put_us(ds, 0x0028, 0x0002, 1);
  put_us(ds, 0x0028, 0x0010, rows);
  put_us(ds, 0x0028, 0x0011, columns);
  put_us(ds, 0x0028, 0x0100, bits);
  put_us(ds, 0x0028, 0x0101, bits);
  put_us(ds, 0x0028, 0x0102, static_cast<uint16_t>(bits - 1));
  put_us(ds, 0x0028, 0x0103, 0);
  gdcm::SmartPointer<gdcm::SequenceOfFragments> fragments = new gdcm::SequenceOfFragments;
  gdcm::Fragment fragment;
  fragment.SetByteValue(stream.data(), static_cast<uint32_t>(stream.size()));
  fragments->AddFragment(fragment);
  gdcm::DataElement pixels(gdcm::Tag(0x7fe0, 0x0010));
  pixels.SetValue(*fragments);
  pixels.SetVLToUndefined();  // GDCM asserts when the VR is set first
  pixels.SetVR(gdcm::VR::OB);
  ds.Replace(pixels);
  w.GetFile().GetHeader().SetDataSetTransferSyntax(syntax);

  const ScratchDir& dir = scratch();
  dir.clear();
  const std::filesystem::path file = dir.path() / "codec.dcm";
  w.SetFileName(file.c_str());
  if (!w.Write()) return 0;
  try {
    const imx::DicomVolume d = imx::read_dicom(file);
    check_volume(d.volume);
    accepted("decoded");
  } catch (const std::exception& e) {
    refused(e);
  }
  return 0;
}
