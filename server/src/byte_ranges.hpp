#pragma once
// Range requests (RFC 9110 section 14), answered by the router for every GET route, never by
// cpp-httplib. cpp-httplib 0.11.4 applies a request's ranges itself to whatever a handler
// answered: any number of them, each a part of a multipart body built in memory (400 ranges of
// a cached frame in a 1.2 KB header made a 2.1 GB body), and to a 200 without making it a 206,
// so that a shared cache could keep 11 bytes of a frame as the whole frame. So the router takes
// the ranges out of every request before routing (take_byte_ranges: the library reads only
// that member), and a GET route's complete answer is then cut here:
//  - one satisfiable range: 206 Partial Content, Content-Range and that slice of the body;
//  - one range that starts past the end: 416 with "Content-Range: bytes */LENGTH";
//  - several ranges, or an If-Range that is not the answer's strong ETag: the whole 200, which
//    RFC 9110 section 14.2 allows (a server may ignore Range), so no answer is ever larger
//    than the representation.
// Every complete 200 of a GET route says "Accept-Ranges: bytes".
#include <httplib.h>

namespace oer::server {

// Empties request.ranges (cpp-httplib's parse of its Range header) and returns what it held.
httplib::Ranges take_byte_ranges(const httplib::Request& request);

// Cuts response, a GET route's answer, to ranges as the header comment says. Only a 200 (or an
// answer without a status yet) is cut.
void answer_byte_ranges(const httplib::Ranges& ranges, const httplib::Request& request,
                        httplib::Response& response);

}  // namespace oer::server
