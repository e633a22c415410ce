// Reading DICOM element values from a GDCM data set without GDCM's asserting Attribute
// templates: text and numbers from the raw bytes, every failure an empty result.
#pragma once
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <gdcmDataSet.h>
#include <gdcmSequenceOfItems.h>
#include <gdcmSmartPointer.h>

namespace imx::detail {

// Turns GDCM's console warnings and errors off, once per process (ours name the file instead).
void quiet_gdcm();

// "(0028,0010)": for messages.
std::string tag_name(uint16_t group, uint16_t element);

// The value of a string element (CS, DS, IS, LO, UI, TM, ...) without trailing spaces and NULs;
// nullopt when absent or empty.
std::optional<std::string> tag_text(const gdcm::DataSet& ds, uint16_t group, uint16_t element);

// The backslash-separated numbers of a DS or IS element; empty when absent or when any value
// does not parse as a finite number.
std::vector<double> tag_numbers(const gdcm::DataSet& ds, uint16_t group, uint16_t element);

// The first number of a DS or IS element.
std::optional<double> tag_number(const gdcm::DataSet& ds, uint16_t group, uint16_t element);

// The numbers of a DS or IS element that is used as it is found: nullopt when absent or empty;
// throws imx::Error "FILE: NAME (gggg,eeee) is present but unusable: 'VALUE' (WHY)" when any value
// is not a finite number or `usable` refuses one, so that a bad value is never taken for a
// missing one (and replaced by a default).
std::optional<std::vector<double>> used_numbers(const gdcm::DataSet& ds, uint16_t group,
                                                uint16_t element, const std::string& file,
                                                const char* name, const char* why,
                                                bool (*usable)(double) = nullptr);

// The message of used_numbers for a value found unusable elsewhere.
std::string unusable_message(const std::string& file, const char* name, uint16_t group,
                             uint16_t element, const std::string& value, const char* why);

// A US (unsigned 16-bit binary) element; GDCM holds binary values in host order.
std::optional<int> tag_us(const gdcm::DataSet& ds, uint16_t group, uint16_t element);

// The values of a binary element of 4- or 8-byte numbers (FL, FD, UL, SL), in host order; empty
// when absent or when the length is not a multiple of the size.
std::vector<double> tag_fd(const gdcm::DataSet& ds, uint16_t group, uint16_t element);
std::vector<double> tag_fl(const gdcm::DataSet& ds, uint16_t group, uint16_t element);
std::vector<uint32_t> tag_ul(const gdcm::DataSet& ds, uint16_t group, uint16_t element);

// The raw bytes of an element (private headers such as Siemens' CSA); empty when absent.
std::string tag_bytes(const gdcm::DataSet& ds, uint16_t group, uint16_t element);

// The element number (0x1000, 0x1100, ...) of the private block that `creator` reserved in
// `group` (its (group,00xx) element names it, trailing spaces ignored); nullopt when none did.
// Private tags mean different things under different creators, so none is read without this.
std::optional<uint16_t> private_block(const gdcm::DataSet& ds, uint16_t group,
                                      const std::string& creator);

// The items of a sequence element; null when absent or not a readable sequence.
gdcm::SmartPointer<gdcm::SequenceOfItems> tag_sequence(const gdcm::DataSet& ds, uint16_t group,
                                                       uint16_t element);

// "UID (name)" of a transfer syntax, for messages: "1.2.840.10008.1.2.4.70 (JPEG Lossless)".
std::string transfer_syntax_label(const std::string& uid);

// Seconds since midnight of a TM value ("HHMMSS.frac", also "HH:MM:SS"); nullopt when malformed.
std::optional<double> parse_dicom_time(const std::string& tm);

}  // namespace imx::detail
