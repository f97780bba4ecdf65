// POST and GET /v1/hotspots (where a frame shows points of the product) and POST and GET
// /v1/pick (the surface a pixel shows): the requests of oer/api/hotspot_request.hpp, answered as
// JSON with the frame's camera, so that a page places its hotspot elements without the frame's
// bytes.
#include <string>

#include "http_exchange.hpp"
#include "oer/api/hotspot_request.hpp"
#include "request_state.hpp"
#include "service_context.hpp"

namespace oer::server {

namespace {

nlohmann::json vector_json(const glm::dvec3& v) {
    return nlohmann::json::array({v.x, v.y, v.z});
}

void answer_placements(ServiceContext& context, const httplib::Request& request,
                       httplib::Response& response, const api::HotspotRequest& hotspots,
                       RequestForm form) {
    const HotspotPlacements placed = context.frame_service.place_hotspots(
        hotspots, form, {request.remote_addr, client_has_gone});
    nlohmann::json answers = nlohmann::json::array();
    for (std::size_t i = 0; i < hotspots.hotspots.size(); ++i) {
        const PointPlacement& placement = placed.placements.at(i);
        answers.push_back({{"name", hotspots.hotspots[i].name},
                           {"x", placement.x},
                           {"y", placement.y},
                           {"depth", placement.depth},
                           {"in_frame", placement.in_frame},
                           {"facing", placement.facing},
                           {"visible", placement.visible()}});
    }
    response.set_header("X-Oer-Camera", camera_header(placed.camera));
    send_json(response, 200,
              {{"camera", camera_header(placed.camera)},
               {"width", hotspots.render.width},
               {"height", hotspots.render.height},
               {"hotspots", std::move(answers)}});
}

void answer_pick(ServiceContext& context, const httplib::Request& request,
                 httplib::Response& response, const api::PickRequest& pick, RequestForm form) {
    const PickedSurface picked =
        context.frame_service.pick(pick, form, {request.remote_addr, client_has_gone});
    nlohmann::json answer = {{"camera", camera_header(picked.camera)},
                             {"width", pick.render.width},
                             {"height", pick.render.height},
                             {"pixel", {pick.pixel.x, pick.pixel.y}},
                             {"hit", picked.spot.has_value()}};
    if (picked.spot) {
        answer["object"] = picked.spot->object;
        answer["primitive"] = picked.spot->primitive;
        answer["triangle"] = picked.spot->triangle;
        answer["barycentric"] = vector_json(picked.spot->barycentric);
        answer["position"] = vector_json(picked.point.position);
        answer["normal"] = vector_json(picked.point.normal);
    }
    response.set_header("X-Oer-Camera", camera_header(picked.camera));
    send_json(response, 200, answer);
}

}  // namespace

void add_hotspot_routes(Router& router, ServiceContext& context) {
    router.post(
        "/v1/hotspots", RoutePolicy{.max_body = context.render_limits.max_body_bytes},
        [](const httplib::Request& request, httplib::Response&) {
            require_json_body(request, "a hotspots request");
        },
        [&context](const httplib::Request& request, httplib::Response& response,
                   const std::string& body) {
            single_query(request, {});
            answer_placements(context, request, response,
                              api::parse_hotspot_json(body, context.render_limits),
                              RequestForm::Json);
        });

    router.get("/v1/hotspots",
               [&context](const httplib::Request& request, httplib::Response& response) {
                   const api::RenderQuery query(request.params.begin(), request.params.end());
                   answer_placements(context, request, response,
                                     api::parse_hotspot_query(query, context.render_limits),
                                     RequestForm::Query);
               });

    router.post(
        "/v1/pick", RoutePolicy{.max_body = context.render_limits.max_body_bytes},
        [](const httplib::Request& request, httplib::Response&) {
            require_json_body(request, "a pick request");
        },
        [&context](const httplib::Request& request, httplib::Response& response,
                   const std::string& body) {
            single_query(request, {});
            answer_pick(context, request, response,
                        api::parse_pick_json(body, context.render_limits), RequestForm::Json);
        });

    router.get(
        "/v1/pick", [&context](const httplib::Request& request, httplib::Response& response) {
            const api::RenderQuery query(request.params.begin(), request.params.end());
            answer_pick(context, request, response,
                        api::parse_pick_query(query, context.render_limits), RequestForm::Query);
        });
}

}  // namespace oer::server
