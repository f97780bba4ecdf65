// Listening: a server never shares its port. cpp-httplib set SO_REUSEPORT, with which a second
// oer-server started on a port in use bound it as well and the kernel split the connections
// between two processes and two data folders.
#include <gtest/gtest.h>

#include <string>

#include "http_support.hpp"
#include "oer/core/error.hpp"

using namespace oer;
using namespace oer::itest;

TEST(Listening, ASecondServerOnAPortInUseRefusesToStartSayingWhy) {
    TempRoot first_root;
    TempRoot second_root;
    TestServer first(test_config(first_root.data()));
    server::ServiceConfig config = test_config(second_root.data());
    config.port = first.port();
    try {
        TestServer second(config);
        FAIL() << "a second server started on port " << first.port();
    } catch (const Error& error) {
        EXPECT_EQ(error.kind(), ErrorKind::Io);
        EXPECT_NE(std::string(error.what())
                      .find(":" + std::to_string(first.port()) + ": Address already in use"),
                  std::string::npos)
            << error.what();
    }
    const auto health = first.client()->Get("/healthz");
    ASSERT_TRUE(health);
    EXPECT_EQ(health->status, 200);
}
