// Data elements for DICOM files a test writes with GDCM: a text value (padded to even length as
// the standard asks: UI with a NUL, other VRs with a space) and an unsigned short.
#pragma once
#include <cstdint>
#include <string>

#include <gdcmDataElement.h>
#include <gdcmDataSet.h>

namespace imx::test {

inline void put_text(gdcm::DataSet& ds, uint16_t group, uint16_t element, gdcm::VR vr,
                     std::string value) {
  if (value.size() % 2 != 0) value.push_back(vr == gdcm::VR::UI ? '\0' : ' ');
  gdcm::DataElement de(gdcm::Tag(group, element));
  de.SetVR(vr);
  de.SetByteValue(value.data(), static_cast<uint32_t>(value.size()));
  ds.Replace(de);
}

inline void put_us(gdcm::DataSet& ds, uint16_t group, uint16_t element, uint16_t value) {
  gdcm::DataElement de(gdcm::Tag(group, element));
  de.SetVR(gdcm::VR::US);
  de.SetByteValue(reinterpret_cast<const char*>(&value), 2);
  ds.Replace(de);
}

}  // namespace imx::test
