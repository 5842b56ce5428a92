// Real data through the whole labelling path: `import bop` of LM-O scene 2, then the labeller with the
// session's own objects.yaml. Every object of the 10 frames must match BOP's scene_gt_info.json:
// bbox_obj within 2 px, px_count_all within 3%. The packed mask files must give back the full-size
// BOP-style masks written beside them, bit for bit.
#include <gtest/gtest.h>
#include <unistd.h>

#include <fstream>
#include <map>

#include "tests/pipeline/label_run_testing.h"
#include "label/labeller.h"
#include "labeller_test_util.h"
#include "session/import/bop_import.h"

namespace mocap {
namespace {

const std::filesystem::path kScene = std::filesystem::path(MOCAP_SHARED_DIR) / "realdata/bop_lmo_scene2";

TEST(LabellerBop, ImportedSceneMatchesSceneGtInfo) {
  const auto dir = testing::FreshDir("bop");
  import::ImportBop(kScene / "test/000002", kScene / "models", dir / "S", BopOptions());
  const SessionReader session = SessionReader::Open(dir / "S");
  LabelRunOptions options;
  options.out_dir = dir / "L";
  options.threads = 2;
  options.output.write_overlay = true;
  options.output.write_bop_masks = true;
  const LabelSummary summary = LabelSession(session, ReadLabelObjects(dir / "S" / "objects.yaml"), LabelRig{}, options);
  EXPECT_EQ(summary.frames, 10);

  std::ifstream gt_file(kScene / "test/000002/scene_gt.json"), info_file(kScene / "test/000002/scene_gt_info.json");
  const auto scene_gt = nlohmann::json::parse(gt_file);
  const auto scene_info = nlohmann::json::parse(info_file);
  // labels.jsonl records by (im_id, body).
  std::map<std::pair<std::string, std::string>, nlohmann::json> records;
  const std::vector<nlohmann::json> lines = testing::ReadJsonLines(dir / "L" / "labels.jsonl");
  for (const auto& r : lines) records[{r["source_id"].get<std::string>(), r["body"].get<std::string>()}] = r;
  EXPECT_GT(testing::CheckPackedMasks(dir / "L", lines), 50);
  int compared = 0;
  for (const std::string im_id : {"3", "8", "17", "27", "36", "38", "39", "41", "47", "58"}) {
    std::map<int, int> seen;
    for (size_t k = 0; k < scene_gt[im_id].size(); ++k) {
      const int obj_id = scene_gt[im_id][k]["obj_id"];
      const std::string body = import::BopBodyName(obj_id, seen[obj_id]++);
      ASSERT_TRUE(records.contains({im_id, body})) << im_id << " " << body;
      const auto& r = records.at({im_id, body});
      const auto& expected = scene_info[im_id][k];
      ASSERT_TRUE(r.contains("bbox_obj")) << r.dump();
      for (int i = 0; i < 4; ++i)
        EXPECT_NEAR(r["bbox_obj"][i].get<int>(), expected["bbox_obj"][i].get<int>(), 2) << im_id << " " << body;
      const double all = expected["px_count_all"];
      EXPECT_NEAR(r["px_count_all"].get<double>(), all, 0.03 * all) << im_id << " " << body;
      EXPECT_EQ(r["object"].get<int>(), obj_id);
      ++compared;
    }
  }
  EXPECT_GT(compared, 50);
  EXPECT_TRUE(std::filesystem::exists(dir / "L" / "bop" / "overlay" / "000000.png"));
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace mocap
