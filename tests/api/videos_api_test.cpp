// Videos of stored episodes over REST against the real server: a job films an episode with its
// progress, serves the file whole and in ranges, is the same job when asked again, and is cancelled
// and forgotten by DELETE; bad requests name their field and start nothing.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <thread>

#include "test_server.hpp"

namespace hrisim::testing {
namespace {

using nlohmann::json;

json json_of(const HttpReply& reply) { return json::parse(reply.body); }

class VideosApi : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    server_ = new TestServer();
    const HttpReply run = http(port(), "POST", "/api/v1/runs", json{{"scenario", "elevator"}, {"seeds", {2}}, {"max_time", 4}}.dump());
    ASSERT_EQ(run.status, 201) << run.body;
    const json report = wait_for_run(port(), json_of(run)["id"]);
    ASSERT_EQ(report["status"], "finished") << report.dump();
    episode_ = report["episodes"][0]["episode_id"];
  }
  static void TearDownTestSuite() {
    delete server_;
    server_ = nullptr;
  }
  static std::uint16_t port() { return server_->port(); }
  static HttpReply ask(const json& body) { return http(port(), "POST", "/api/v1/episodes/" + episode_ + "/videos", body.dump()); }
  /// Polls a job until it has left the queue and the camera; its last status, and every status seen.
  static json wait_for_video(const std::string& id, std::vector<json>* seen = nullptr) {
    for (int i = 0; i < 1200; ++i) {
      const json status = json_of(http(port(), "GET", "/api/v1/videos/" + id));
      if (seen) seen->push_back(status);
      if (status["status"] != "queued" && status["status"] != "filming") return status;
      std::this_thread::sleep_for(std::chrono::milliseconds(25));
    }
    throw std::runtime_error("video " + id + " did not end");
  }
  static TestServer* server_;
  static std::string episode_;
};
TestServer* VideosApi::server_ = nullptr;
std::string VideosApi::episode_;

TEST_F(VideosApi, AnEpisodeIsFilmedWithItsProgressAndServedWholeOrInRanges) {
  const HttpReply created = ask({{"camera", "robot.head_rgbd"}, {"width", 128}, {"fps", 10}});
  ASSERT_EQ(created.status, 202) << created.body;
  const json job = json_of(created);
  EXPECT_EQ(created.headers.at("location"), "/api/v1/videos/" + job["id"].get<std::string>());
  EXPECT_EQ(job["episode"], episode_);
  EXPECT_EQ(job["camera"], "robot.head_rgbd");
  EXPECT_EQ(job["width"], 128);
  EXPECT_EQ(job["height"], 96) << "a width alone keeps the camera's 4:3";
  EXPECT_EQ(job["progress"]["ticks"], 240) << "4 s at 60 Hz";

  std::vector<json> seen;
  const json done = wait_for_video(job["id"], &seen);
  ASSERT_EQ(done["status"], "done") << done.dump();
  // 4 s at 60 Hz, a frame every 6 ticks, the first at tick 0: 41 frames, as `hrisim render` films it.
  EXPECT_EQ(done["frames"], 41);
  EXPECT_EQ(done["video_fps"], 10.0);
  EXPECT_EQ(done["codec"], "h264");
  EXPECT_TRUE(done["matches_stored_episode"].get<bool>()) << "the replay is the stored episode, tick for tick";
  EXPECT_EQ(done["progress"]["fraction"], 1.0);
  double last_fraction = 0.0;
  for (const json& status : seen) {
    EXPECT_GE(status["progress"]["fraction"].get<double>(), last_fraction) << "progress never goes back";
    last_fraction = status["progress"]["fraction"];
  }

  const HttpReply file = http(port(), "GET", done["file"].get<std::string>());
  ASSERT_EQ(file.status, 200);
  EXPECT_EQ(file.headers.at("content-type"), "video/mp4");
  EXPECT_EQ(file.headers.at("content-disposition"), "attachment; filename=\"" + episode_ + "-robot.head_rgbd.mp4\"");
  EXPECT_EQ(file.headers.at("accept-ranges"), "bytes");
  EXPECT_EQ(file.body.size(), done["bytes"].get<std::size_t>());
  EXPECT_EQ(file.body.substr(4, 4), "ftyp") << "an MP4 container";

  const std::string size = std::to_string(file.body.size());
  const HttpReply head = http(port(), "GET", done["file"].get<std::string>(), "", "Range: bytes=0-99\r\n");
  EXPECT_EQ(head.status, 206);
  EXPECT_EQ(head.headers.at("content-range"), "bytes 0-99/" + size);
  EXPECT_EQ(head.body, file.body.substr(0, 100));
  const HttpReply tail = http(port(), "GET", done["file"].get<std::string>(), "", "Range: bytes=-10\r\n");
  EXPECT_EQ(tail.status, 206);
  EXPECT_EQ(tail.body, file.body.substr(file.body.size() - 10));
  const HttpReply rest = http(port(), "GET", done["file"].get<std::string>(), "", "Range: bytes=100-\r\n");
  EXPECT_EQ(rest.body, file.body.substr(100));
  const HttpReply outside = http(port(), "GET", done["file"].get<std::string>(), "", "Range: bytes=" + size + "-\r\n");
  EXPECT_EQ(outside.status, 416);
  EXPECT_EQ(outside.headers.at("content-range"), "bytes */" + size);

  const HttpReply again = ask({{"camera", "robot.head_rgbd"}, {"width", 128}, {"fps", 10}});
  EXPECT_EQ(again.status, 200) << "the same episode and options are the same job";
  EXPECT_EQ(json_of(again)["id"], job["id"]);
  EXPECT_EQ(json_of(again)["status"], "done");

  EXPECT_EQ(http(port(), "DELETE", "/api/v1/videos/" + job["id"].get<std::string>()).status, 204);
  EXPECT_EQ(http(port(), "GET", "/api/v1/videos/" + job["id"].get<std::string>()).status, 404);
  EXPECT_EQ(http(port(), "GET", done["file"].get<std::string>()).status, 404);
  EXPECT_EQ(http(port(), "DELETE", "/api/v1/videos/" + job["id"].get<std::string>()).status, 404);
}

// Issue 40, finding 10: "bytes= 0-1" and "bytes=+1-2" returned bytes from the end, "bytes=5-3" was 416,
// "BYTES=" was ignored, and a range past the end was 416 labelled JSON with an empty body.
TEST_F(VideosApi, RangeHeadersAreReadAsRfc9110Says) {
  const HttpReply created = ask({{"camera", "robot.head_rgbd"}, {"width", 64}, {"fps", 2}});
  ASSERT_EQ(created.status, 202) << created.body;
  const json done = wait_for_video(json_of(created)["id"]);
  ASSERT_EQ(done["status"], "done") << done.dump();
  const std::string path = done["file"];
  const HttpReply whole = http(port(), "GET", path);
  ASSERT_EQ(whole.status, 200);
  const std::string size = std::to_string(whole.body.size());
  for (const std::string invalid : {"bytes= 0-1", "bytes=+1-2", "bytes=5-3", "bytes=0-1,4-5"}) {
    const HttpReply reply = http(port(), "GET", path, "", "Range: " + invalid + "\r\n");
    EXPECT_EQ(reply.status, 200) << invalid << ": ignored, the whole file";
    EXPECT_EQ(reply.body, whole.body) << invalid;
    EXPECT_FALSE(reply.headers.contains("content-range")) << invalid;
  }
  const HttpReply upper = http(port(), "GET", path, "", "Range: BYTES=1-2\r\n");
  EXPECT_EQ(upper.status, 206);
  EXPECT_EQ(upper.headers.at("content-range"), "bytes 1-2/" + size);
  EXPECT_EQ(upper.body, whole.body.substr(1, 2));
  const HttpReply outside = http(port(), "GET", path, "", "Range: bytes=" + size + "-\r\n");
  EXPECT_EQ(outside.status, 416);
  EXPECT_EQ(outside.headers.at("content-range"), "bytes */" + size);
  EXPECT_FALSE(outside.headers.contains("content-type")) << "no body, so no type";
  EXPECT_EQ(outside.body, "");
}

TEST_F(VideosApi, WebmFramesHaveEvenSides) {
  const HttpReply created = ask({{"width", 101}, {"fps", 5}, {"format", "webm"}});
  ASSERT_EQ(created.status, 202) << created.body;
  EXPECT_EQ(json_of(created)["width"], 100) << "an odd side is rounded down";
  const json done = wait_for_video(json_of(created)["id"]);
  ASSERT_EQ(done["status"], "done") << done.dump();
  EXPECT_EQ(done["codec"], "vp8");
  const HttpReply file = http(port(), "GET", done["file"].get<std::string>());
  EXPECT_EQ(file.headers.at("content-type"), "video/webm");
  EXPECT_EQ(file.body.substr(0, 4), "\x1a\x45\xdf\xa3") << "a Matroska (WebM) container";
}

TEST_F(VideosApi, TheCamerasToFilmWithAreListed) {
  const HttpReply reply = http(port(), "GET", "/api/v1/episodes/" + episode_ + "/cameras");
  ASSERT_EQ(reply.status, 200) << reply.body;
  const json cameras = json_of(reply)["cameras"];
  std::vector<std::string> names;
  for (const json& camera : cameras) names.push_back(camera["name"]);
  EXPECT_EQ(names, (std::vector<std::string>{"overview", "follow", "robot.head_rgbd", "robot.hand_camera"}));
  EXPECT_EQ(http(port(), "GET", "/api/v1/episodes/no-such-episode/cameras").status, 404);
}

TEST_F(VideosApi, AJobCancelledWhileFilmingLeavesNothing) {
  // A long video at a high rate: still filming when asked for its file a moment later.
  const HttpReply created = ask({{"fps", 60}, {"width", 1280}});
  ASSERT_EQ(created.status, 202) << created.body;
  const std::string id = json_of(created)["id"];
  const HttpReply early = http(port(), "GET", "/api/v1/videos/" + id + "/file");
  EXPECT_EQ(early.status, 409) << early.body;
  EXPECT_NE(json_of(early)["error"]["message"].get<std::string>().find("not done"), std::string::npos) << early.body;
  EXPECT_EQ(http(port(), "DELETE", "/api/v1/videos/" + id).status, 204);
  EXPECT_EQ(http(port(), "GET", "/api/v1/videos/" + id).status, 404);
  // Asked again, it is a new job that films to its end.
  const HttpReply renewed = ask({{"fps", 60}, {"width", 1280}});
  EXPECT_EQ(renewed.status, 202) << renewed.body;
  EXPECT_EQ(json_of(renewed)["id"], id) << "the same options name the same job";
  EXPECT_EQ(wait_for_video(id)["status"], "done");
}

TEST_F(VideosApi, BadRequestsNameTheirFieldAndStartNothing) {
  struct Case {
    json body;
    std::string pointer;
  };
  for (const Case& bad : std::vector<Case>{{{{"camera", "ceiling"}}, "/camera"},
                                           {{{"camera", 3}}, "/camera"},
                                           {{{"fps", 0}}, "/fps"},
                                           {{{"fps", 121}}, "/fps"},
                                           {{{"width", 8}}, "/width"},
                                           {{{"height", 4000}}, "/height"},
                                           {{{"format", "gif"}}, "/format"},
                                           {{{"colour", "red"}}, "/colour"}}) {
    const HttpReply reply = ask(bad.body);
    EXPECT_EQ(reply.status, 400) << bad.body.dump() << " → " << reply.body;
    EXPECT_EQ(json_of(reply)["error"]["details"]["pointer"], bad.pointer) << reply.body;
  }
  const HttpReply camera = ask({{"camera", "ceiling"}});
  EXPECT_NE(json_of(camera)["error"]["message"].get<std::string>().find("(overview, follow, robot.head_rgbd, robot.hand_camera)"), std::string::npos)
      << "the message lists the cameras there are: " << camera.body;
  EXPECT_EQ(http(port(), "POST", "/api/v1/episodes/" + episode_ + "/videos", "{not json").status, 400);
  EXPECT_EQ(http(port(), "POST", "/api/v1/episodes/no-such-episode/videos", "{}").status, 404);
  EXPECT_EQ(http(port(), "GET", "/api/v1/videos/v0000").status, 404);
  EXPECT_EQ(http(port(), "GET", "/api/v1/videos/v0000/file").status, 404);
}

}  // namespace
}  // namespace hrisim::testing
