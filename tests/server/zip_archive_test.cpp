// The stored ZIP of a job's frames (zip_archive.hpp): CRC-32 against its check value, and an
// archive read back by Python's zipfile, an implementation of its own, which checks every
// entry's CRC (testzip) and its bytes.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "zip_archive.hpp"

using namespace oer::server;

TEST(ZipArchive, Crc32HasItsCheckValue) {
    EXPECT_EQ(crc32("123456789"), 0xCBF43926u);  // the catalogue's check value of CRC-32/ISO-HDLC
    EXPECT_EQ(crc32(""), 0u);
}

TEST(ZipArchive, IsReadBackByAnotherImplementation) {
    ZipWriter zip;
    const std::string png("\x89PNG\r\n\x1a\n and more bytes");
    std::string archive = zip.entry("Red-000.png", png);
    archive += zip.entry("Red-001.jpeg", std::string(70000, 'x'));
    archive += zip.finish();
    const auto path = std::filesystem::temp_directory_path() /
                      ("oer-zip-test-" + std::to_string(::getpid()) + ".zip");
    std::ofstream(path, std::ios::binary) << archive;
    const std::string check =
        "python3 -c \"import sys, zipfile; z = zipfile.ZipFile(sys.argv[1]); "
        "assert z.testzip() is None; assert z.namelist() == ['Red-000.png', 'Red-001.jpeg']; "
        "assert z.read('Red-000.png') == b'\\x89PNG\\r\\n\\x1a\\n and more bytes'; "
        "assert z.read('Red-001.jpeg') == b'x' * 70000\" " +
        path.string();
    EXPECT_EQ(std::system(check.c_str()), 0) << check;
    std::filesystem::remove(path);
}
