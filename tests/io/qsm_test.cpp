// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
//
// Cylinder-model import (TreeQSM text, SimpleForest CSV): node sharing, parent splits,
// connectors, tiny and duplicate cylinders, orphans, located errors, and the two real models in
// ../shared/data/trees when present.
#include "ramiform/io/qsm_io.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "io/io_test_util.h"
#include "ramiform/core/errors.h"
#include "ramiform/io/skeleton_io.h"

namespace ramiform {
namespace {

using io_test::TempDir;
using io_test::write_bytes;
namespace fs = std::filesystem;

// One TreeQSM line: radius, length, start, axis, parent (1-based, 0 = root), then the extra
// columns real files carry (extension, added, unmodified radius, branch, order, position).
std::string tq(double r, double len, const Vec3& s, const Vec3& axis, int parent) {
  std::ostringstream o;
  o.precision(17);
  o << r << '\t' << len << '\t' << s.x() << '\t' << s.y() << '\t' << s.z() << '\t' << axis.x()
    << '\t' << axis.y() << '\t' << axis.z() << '\t' << parent << "\t0\t0\t" << r << "\t1\t0\t1\n";
  return o.str();
}

// One SimpleForest line with the rTwig column set (the unused columns hold zeros).
std::string sf(int id, int parent, const Vec3& s, const Vec3& e, double r) {
  std::ostringstream o;
  o.precision(17);
  o << id << ',' << parent << ',' << s.x() << ',' << s.y() << ',' << s.z() << ',' << e.x() << ','
    << e.y() << ',' << e.z() << ',' << r << ',' << (e - s).norm() << ",0,0,0,-1,0,0,0\n";
  return o.str();
}

const char* const kSfHeader =
    " ID, parentID, startX, startY, startZ, endX, endY, endZ, radius, length, growthLength, "
    "averagePointDistance,segmentID, parentSegmentID, branchOrder, reverseBranchOrder, "
    "branchID\n";

double segment_distance(const Vec3& a, const Vec3& b, const Vec3& x) {
  const Vec3 u = b - a;
  const double t = std::clamp((x - a).dot(u) / u.squaredNorm(), 0.0, 1.0);
  return (x - (a + t * u)).norm();
}

// Distance from `x` to the nearest edge (or node, for a skeleton without edges).
double distance_to_skeleton(const Skeleton& s, const Vec3& x) {
  double best = std::numeric_limits<double>::infinity();
  for (const auto& n : s.nodes) best = std::min(best, (n.position - x).norm());
  for (const auto& e : s.edges) {
    best = std::min(best, segment_distance(s.nodes[e[0]].position, s.nodes[e[1]].position, x));
  }
  return best;
}

// Index of the node at `x` (exactly), or -1.
int node_at(const Skeleton& s, const Vec3& x) {
  for (std::size_t i = 0; i < s.nodes.size(); ++i) {
    if ((s.nodes[i].position - x).norm() < 1e-12) return static_cast<int>(i);
  }
  return -1;
}

bool has_edge(const Skeleton& s, int a, int b) {
  for (const auto& e : s.edges) {
    if ((static_cast<int>(e[0]) == a && static_cast<int>(e[1]) == b) ||
        (static_cast<int>(e[0]) == b && static_cast<int>(e[1]) == a)) {
      return true;
    }
  }
  return false;
}

// The node-count identity of the importer: a start node for the root, an end node per cylinder
// unless merged or reused, one node per connector and per split.
void expect_counts_add_up(const Skeleton& s, const QsmImportReport& r) {
  EXPECT_EQ(s.node_count(),
            r.cylinders + 1 + r.connectors + r.split_parents - r.merged_tiny - r.duplicates);
  EXPECT_EQ(connected_components(s).count, 1U);
  EXPECT_NO_THROW(validate(s));
}

const Vec3 kZ(0, 0, 1);
const Vec3 kX(1, 0, 0);

TEST(TreeQsm, ChainOfCylindersSharesNodesAndAveragesRadii) {
  const std::string text = tq(0.3, 1.0, {0, 0, 0}, kZ, 0) + tq(0.2, 1.0, {0, 0, 1}, kZ, 1) +
                           tq(0.1, 2.0, {0, 0, 2}, {0, 0, 2}, 2);  // axis not unit: normalized
  QsmImportReport r;
  const Skeleton s = parse_treeqsm(text, "chain.txt", &r);
  ASSERT_EQ(s.node_count(), 4U);
  ASSERT_EQ(s.edge_count(), 3U);
  const double z[] = {0, 1, 2, 4};
  const double radius[] = {0.3, 0.25, 0.15, 0.1};  // mean of the cylinders ending and starting
  for (int i = 0; i < 4; ++i) {
    const int v = node_at(s, Vec3(0, 0, z[i]));
    ASSERT_GE(v, 0) << "no node at z = " << z[i];
    EXPECT_DOUBLE_EQ(s.nodes[static_cast<std::size_t>(v)].radius, radius[i]) << "z = " << z[i];
    if (i > 0) {
      EXPECT_TRUE(has_edge(s, node_at(s, Vec3(0, 0, z[i - 1])), v));
    }
  }
  EXPECT_EQ(r.cylinders, 3U);
  EXPECT_EQ(r.connectors + r.split_parents + r.merged_tiny + r.reattached + r.duplicates, 0U);
  expect_counts_add_up(s, r);
}

TEST(TreeQsm, ChildStartingOnTheSurfaceMidCylinderSplitsTheParent) {
  // Trunk 0..2 along z (radius 0.2); a branch starts on its surface at height 1 and goes +x.
  const std::string text = tq(0.2, 2.0, {0, 0, 0}, kZ, 0) + tq(0.1, 1.0, {0.2, 0, 1}, kX, 1);
  QsmImportReport r;
  const Skeleton s = parse_treeqsm(text, "fork.txt", &r);
  EXPECT_EQ(r.split_parents, 1U);
  EXPECT_EQ(r.connectors, 1U);
  ASSERT_EQ(s.node_count(), 5U);
  ASSERT_EQ(s.edge_count(), 4U);
  const int base = node_at(s, {0, 0, 0});
  const int split = node_at(s, {0, 0, 1});
  const int top = node_at(s, {0, 0, 2});
  const int child_start = node_at(s, {0.2, 0, 1});
  const int child_end = node_at(s, {1.2, 0, 1});
  ASSERT_GE(std::min({base, split, top, child_start, child_end}), 0);
  EXPECT_TRUE(has_edge(s, base, split));
  EXPECT_TRUE(has_edge(s, split, top));
  EXPECT_TRUE(has_edge(s, split, child_start));  // the connector
  EXPECT_TRUE(has_edge(s, child_start, child_end));
  EXPECT_DOUBLE_EQ(s.nodes[static_cast<std::size_t>(split)].radius, 0.2);
  EXPECT_DOUBLE_EQ(s.nodes[static_cast<std::size_t>(child_start)].radius, 0.1);
  EXPECT_DOUBLE_EQ(s.nodes[static_cast<std::size_t>(child_end)].radius, 0.1);
  expect_counts_add_up(s, r);
}

TEST(TreeQsm, ChildrenNearAnEndOrNearEachOtherShareANode) {
  // Two branches 0.02 apart at mid-height share one split node (at their mean); a third near
  // the top (0.04 < 0.25 * 0.2 below it) attaches to the top node without a split.
  const std::string text = tq(0.2, 2.0, {0, 0, 0}, kZ, 0) + tq(0.05, 0.5, {0.2, 0, 1.0}, kX, 1) +
                           tq(0.05, 0.5, {-0.2, 0, 1.02}, -kX, 1) +
                           tq(0.05, 0.5, {0, 0.2, 1.96}, {0, 1, 0}, 1);
  QsmImportReport r;
  const Skeleton s = parse_treeqsm(text, "forks.txt", &r);
  EXPECT_EQ(r.split_parents, 1U);
  EXPECT_EQ(r.connectors, 3U);
  const int split = node_at(s, {0, 0, 1.01});
  const int top = node_at(s, {0, 0, 2});
  ASSERT_GE(split, 0);
  ASSERT_GE(top, 0);
  EXPECT_TRUE(has_edge(s, split, node_at(s, {0.2, 0, 1.0})));
  EXPECT_TRUE(has_edge(s, split, node_at(s, {-0.2, 0, 1.02})));
  EXPECT_TRUE(has_edge(s, top, node_at(s, {0, 0.2, 1.96})));
  expect_counts_add_up(s, r);
}

TEST(TreeQsm, ContinuationWithASmallGapSharesTheNodeAndALargeGapGetsAConnector) {
  // The second cylinder starts 0.05 beside the first one's end (< 0.5 * 0.2): shared node at
  // the parent's end. The third starts 0.5 above the second's end: connector across the gap.
  const std::string text = tq(0.2, 1.0, {0, 0, 0}, kZ, 0) + tq(0.2, 1.0, {0.05, 0, 1}, kZ, 1) +
                           tq(0.2, 1.0, {0.05, 0, 2.5}, kZ, 2);
  QsmImportReport r;
  const Skeleton s = parse_treeqsm(text, "gaps.txt", &r);
  EXPECT_EQ(r.connectors, 1U);
  const int joint = node_at(s, {0, 0, 1});
  const int second_end = node_at(s, {0.05, 0, 2});
  const int third_start = node_at(s, {0.05, 0, 2.5});
  ASSERT_GE(std::min({joint, second_end, third_start}), 0);
  EXPECT_EQ(node_at(s, {0.05, 0, 1}), -1);  // no node at the second cylinder's own start
  EXPECT_TRUE(has_edge(s, joint, second_end));
  EXPECT_TRUE(has_edge(s, second_end, third_start));
  expect_counts_add_up(s, r);
}

TEST(TreeQsm, TinyCylindersAreMerged) {
  // A 0.01-long cylinder of radius 0.2 (< 0.25 r) between two normal ones, and a zero-length
  // one at the tip.
  const std::string text = tq(0.2, 1.0, {0, 0, 0}, kZ, 0) + tq(0.2, 0.01, {0, 0, 1}, kZ, 1) +
                           tq(0.2, 1.0, {0, 0, 1.01}, kZ, 2) + tq(0.1, 0.0, {0, 0, 2.01}, kZ, 3);
  QsmImportReport r;
  const Skeleton s = parse_treeqsm(text, "tiny.txt", &r);
  EXPECT_EQ(r.merged_tiny, 2U);
  ASSERT_EQ(s.node_count(), 3U);
  ASSERT_EQ(s.edge_count(), 2U);
  const int mid = node_at(s, {0, 0, 1});
  const int tip = node_at(s, {0, 0, 2.01});
  ASSERT_GE(mid, 0);
  ASSERT_GE(tip, 0);
  EXPECT_TRUE(has_edge(s, node_at(s, {0, 0, 0}), mid));
  EXPECT_TRUE(has_edge(s, mid, tip));
  EXPECT_DOUBLE_EQ(s.nodes[static_cast<std::size_t>(tip)].radius, 0.15);
  expect_counts_add_up(s, r);
}

TEST(TreeQsm, RunsOfTinyCylindersDoNotCollapse) {
  // Ten cylinders of length 0.04 (each tiny for radius 0.2) make a 0.4 long run: merging is
  // measured from the node, so the run keeps nodes at most 0.05 apart from the cylinder ends.
  std::string text = tq(0.2, 1.0, {0, 0, 0}, kZ, 0);
  for (int i = 0; i < 10; ++i) text += tq(0.2, 0.04, {0, 0, 1.0 + 0.04 * i}, kZ, i + 1);
  QsmImportReport r;
  const Skeleton s = parse_treeqsm(text, "run.txt", &r);
  EXPECT_LT(distance_to_skeleton(s, {0, 0, 1.4}), 0.05 + 1e-12);
  EXPECT_EQ(r.merged_tiny, 10U - (s.node_count() - 2));
  for (const auto& e : s.edges) {
    EXPECT_GE((s.nodes[e[0]].position - s.nodes[e[1]].position).norm(), 0.05 - 1e-12);
  }
  expect_counts_add_up(s, r);
}

TEST(TreeQsm, DuplicateCylindersAddNoEdges) {
  // Cylinder 2 repeats cylinder 1 as its child; cylinders 3 and 4 are identical siblings.
  const std::string text = tq(0.2, 1.0, {0, 0, 0}, kZ, 0) + tq(0.2, 1.0, {0, 0, 0}, kZ, 1) +
                           tq(0.1, 1.0, {0, 0, 1}, kZ, 1) + tq(0.1, 1.0, {0, 0, 1}, kZ, 1);
  QsmImportReport r;
  const Skeleton s = parse_treeqsm(text, "dup.txt", &r);
  EXPECT_EQ(r.duplicates, 2U);
  ASSERT_EQ(s.node_count(), 3U);
  ASSERT_EQ(s.edge_count(), 2U);
  expect_counts_add_up(s, r);
}

TEST(TreeQsm, InvalidParentsAreReattachedToTheNearestAxis) {
  // Cylinder 3 names parent 99 (there are 4), cylinder 4 names itself: both are attached to the
  // nearest axis, which for cylinder 3 is the trunk at height 1.5 and for 4 cylinder 3.
  const std::string text = tq(0.2, 2.0, {0, 0, 0}, kZ, 0) + tq(0.1, 1.0, {0, 0, 2}, kZ, 1) +
                           tq(0.05, 1.0, {0.3, 0, 1.5}, kX, 99) +
                           tq(0.05, 0.5, {1.3, 0, 1.5}, kX, 4);
  QsmImportReport r;
  const Skeleton s = parse_treeqsm(text, "orphans.txt", &r);
  EXPECT_EQ(r.reattached, 2U);
  EXPECT_EQ(connected_components(s).count, 1U);
  const int split = node_at(s, {0, 0, 1.5});
  ASSERT_GE(split, 0);
  EXPECT_TRUE(has_edge(s, split, node_at(s, {0.3, 0, 1.5})));
  EXPECT_TRUE(has_edge(s, node_at(s, {1.3, 0, 1.5}), node_at(s, {1.8, 0, 1.5})));
  expect_counts_add_up(s, r);
}

TEST(TreeQsm, ParentCyclesAndSecondRootsBecomeOneTree) {
  // 2 and 3 are each other's parents; 4 is a second root (parent 0).
  const std::string text = tq(0.2, 1.0, {0, 0, 0}, kZ, 0) + tq(0.1, 1.0, {0, 0, 1}, kZ, 3) +
                           tq(0.1, 1.0, {0, 0, 2}, kZ, 2) + tq(0.1, 1.0, {5, 0, 0}, kZ, 0);
  QsmImportReport r;
  const Skeleton s = parse_treeqsm(text, "cycle.txt", &r);
  EXPECT_EQ(r.reattached, 2U);
  EXPECT_EQ(s.edge_count() + 1, s.node_count());  // a tree
  expect_counts_add_up(s, r);
}

TEST(TreeQsm, HeaderLineCommentsAndBlankLinesAreSkipped) {
  const std::string text = "radius\tlength\tstart_point\taxis_direction\tparent\n\n# comment\n" +
                           tq(0.2, 1.0, {0, 0, 0}, kZ, 0) + "\r\n" +
                           "0.1 1 0 0 1 0 0 1 1\n";  // only the 9 used columns
  const Skeleton s = parse_treeqsm(text, "h.txt");
  EXPECT_EQ(s.node_count(), 3U);
}

TEST(TreeQsm, BadInputIsReportedWithTheLine) {
  const std::string ok = tq(0.2, 1.0, {0, 0, 0}, kZ, 0);
  EXPECT_INPUT_ERROR_AT(parse_treeqsm(ok + "0.1 abc 0 0 1 0 0 1 1\n", "t.txt"), "t.txt", 2,
                        "length: expected a number, got 'abc'");
  EXPECT_INPUT_ERROR_AT(parse_treeqsm(ok + "\n" + "nan 1 0 0 1 0 0 1 1\n", "t.txt"), "t.txt", 3,
                        "radius: 'nan' is not a finite number");
  EXPECT_INPUT_ERROR_AT(parse_treeqsm(ok + "inf 1 0 0 1 0 0 1 1\n", "t.txt"), "t.txt", 2,
                        "not a finite number");
  EXPECT_INPUT_ERROR_AT(parse_treeqsm(ok + "-0.1 1 0 0 1 0 0 1 1\n", "t.txt"), "t.txt", 2,
                        "radius must be > 0, got -0.1");
  EXPECT_INPUT_ERROR_AT(parse_treeqsm(ok + "0 1 0 0 1 0 0 1 1\n", "t.txt"), "t.txt", 2,
                        "radius must be > 0");
  EXPECT_INPUT_ERROR_AT(parse_treeqsm(ok + "0.1 -1 0 0 1 0 0 1 1\n", "t.txt"), "t.txt", 2,
                        "length must be >= 0");
  EXPECT_INPUT_ERROR_AT(parse_treeqsm(ok + "0.1 1 0 0 1 0 0 0 1\n", "t.txt"), "t.txt", 2,
                        "axis direction must be a non-zero vector");
  EXPECT_INPUT_ERROR_AT(parse_treeqsm(ok + "0.1 1 0 0 1 0 0 1\n", "t.txt"), "t.txt", 2,
                        "expected at least 9 columns");
  EXPECT_INPUT_ERROR_AT(parse_treeqsm(ok + "0.1 1 0 0 1 0 0 1 1.5\n", "t.txt"), "t.txt", 2,
                        "parent: '1.5' is not a whole number");
  EXPECT_INPUT_ERROR_AT(parse_treeqsm(ok + "0.1 1 0 0 1e999 0 0 1 1\n", "t.txt"), "t.txt", 2,
                        "start point: '1e999' is out of range");
  // A non-number on the first line is a header; on a later line it is an error.
  EXPECT_INPUT_ERROR_AT(parse_treeqsm("radius length\n" + ok + "radius length\n", "t.txt"), "t.txt",
                        3, "expected at least 9 columns");
  EXPECT_INPUT_ERROR_AT(parse_treeqsm(" \n\n", "t.txt"), "t.txt", 0, "file is empty");
  EXPECT_INPUT_ERROR_AT(parse_treeqsm("radius length\n", "t.txt"), "t.txt", 0, "no cylinders");
}

TEST(SimpleForest, ChainAndForkShareNodes) {
  // Ids out of order; the fork's children start exactly at the parent's end.
  const std::string text = std::string(kSfHeader) + sf(10, 11, {0, 0, 1}, {0, 0, 2}, 0.15) +
                           sf(11, -1, {0, 0, 0}, {0, 0, 1}, 0.2) +
                           sf(12, 10, {0, 0, 2}, {0.5, 0, 2.5}, 0.05) +
                           sf(13, 10, {0, 0, 2}, {0, 0, 3}, 0.1);
  QsmImportReport r;
  const Skeleton s = parse_simpleforest(text, "sf.csv", &r);
  EXPECT_EQ(r.cylinders, 4U);
  ASSERT_EQ(s.node_count(), 5U);
  ASSERT_EQ(s.edge_count(), 4U);
  const int fork = node_at(s, {0, 0, 2});
  ASSERT_GE(fork, 0);
  // Mean of the largest radius ending (0.15) and the largest starting (0.1) there.
  EXPECT_DOUBLE_EQ(s.nodes[static_cast<std::size_t>(fork)].radius, 0.125);
  EXPECT_TRUE(has_edge(s, fork, node_at(s, {0.5, 0, 2.5})));
  EXPECT_TRUE(has_edge(s, fork, node_at(s, {0, 0, 3})));
  expect_counts_add_up(s, r);
}

TEST(SimpleForest, UnknownParentIsReattached) {
  const std::string text = std::string(kSfHeader) + sf(0, -1, {0, 0, 0}, {0, 0, 2}, 0.2) +
                           sf(1, 42, {0.2, 0, 1}, {1, 0, 1}, 0.05);
  QsmImportReport r;
  const Skeleton s = parse_simpleforest(text, "sf.csv", &r);
  EXPECT_EQ(r.reattached, 1U);
  EXPECT_EQ(r.split_parents, 1U);
  EXPECT_EQ(r.connectors, 1U);
  expect_counts_add_up(s, r);
}

TEST(SimpleForest, BadInputIsReportedWithTheLine) {
  const std::string h = kSfHeader;
  const std::string ok = sf(0, -1, {0, 0, 0}, {0, 0, 1}, 0.2);
  EXPECT_INPUT_ERROR_AT(
      parse_simpleforest("ID,parentID,startX,startY,startZ,endX,endY,endZ\n" + ok, "sf.csv"),
      "sf.csv", 1, "missing column 'radius'");
  EXPECT_INPUT_ERROR_AT(parse_simpleforest(h + ok + "1,0,0,0,1\n", "sf.csv"), "sf.csv", 3,
                        "expected 17 fields like the header (line 1), got 5");
  EXPECT_INPUT_ERROR_AT(parse_simpleforest(h + ok + "1,0,,0,1\n", "sf.csv"), "sf.csv", 3,
                        "empty field");
  EXPECT_INPUT_ERROR_AT(parse_simpleforest(h + ok + sf(0, 0, {0, 0, 1}, {0, 0, 2}, 0.1), "sf.csv"),
                        "sf.csv", 3, "ID 0 repeats the ID of line 2");
  std::string bad = sf(1, 0, {0, 0, 1}, {0, 0, 2}, 0.1);
  bad.replace(bad.find(",0.10000000000000001,"), 21, ",NaN,");
  EXPECT_INPUT_ERROR_AT(parse_simpleforest(h + ok + bad, "sf.csv"), "sf.csv", 3,
                        "radius: 'NaN' is not a finite number");
  EXPECT_INPUT_ERROR_AT(parse_simpleforest(h + ok + sf(1, 0, {0, 0, 1}, {0, 0, 2}, -1), "sf.csv"),
                        "sf.csv", 3, "radius must be > 0");
  EXPECT_INPUT_ERROR_AT(
      parse_simpleforest(h + "\n" + ok + "1,0,0,0,2x,0,0,2,0.1,1,0,0,0,-1,0,0,0\n", "sf.csv"),
      "sf.csv", 4, "startZ: expected a number, got '2x'");
  EXPECT_INPUT_ERROR_AT(parse_simpleforest(h, "sf.csv"), "sf.csv", 0, "no cylinders");
}

TEST(QsmIo, ReadSkeletonDispatchesByExtensionAndHeader) {
  TempDir dir;
  const std::string treeqsm = tq(0.2, 1.0, {0, 0, 0}, kZ, 0) + tq(0.1, 1.0, {0, 0, 1}, kZ, 1);
  const std::string simpleforest = std::string(kSfHeader) + sf(0, -1, {0, 0, 0}, {0, 0, 1}, 0.2) +
                                   sf(1, 0, {0, 0, 1}, {0, 0, 2}, 0.1);
  write_bytes(dir.file("a.txt"), treeqsm);
  write_bytes(dir.file("b.CSV"), simpleforest);
  write_bytes(dir.file("c.txt"), simpleforest);
  for (const char* name : {"a.txt", "b.CSV", "c.txt"}) {
    QsmImportReport r;
    SkeletonReadOptions options;
    options.qsm_report = &r;
    const Skeleton s = read_skeleton(dir.file(name), options);
    EXPECT_EQ(s.node_count(), 3U) << name;
    EXPECT_EQ(r.cylinders, 2U) << name;
  }
  EXPECT_EQ(read_treeqsm(dir.file("a.txt")).node_count(), 3U);
  EXPECT_EQ(read_simpleforest(dir.file("b.CSV")).node_count(), 3U);
  EXPECT_TRUE(looks_like_simpleforest(simpleforest));
  EXPECT_FALSE(looks_like_simpleforest(treeqsm));
  // A TreeQSM error from read_skeleton names the file and the line.
  write_bytes(dir.file("bad.txt"), treeqsm + "0.1 1 0 0 1 0 0 1 x\n");
  EXPECT_INPUT_ERROR_AT(read_skeleton(dir.file("bad.txt")), dir.file("bad.txt"), 3,
                        "parent: expected a number, got 'x'");
  EXPECT_INPUT_ERROR_AT(read_skeleton(dir.file("x.skel")), dir.file("x.skel"), 0,
                        ".csv SimpleForest, .txt TreeQSM");
}

// ---- the real models --------------------------------------------------------------------------

struct RealCylinder {
  Vec3 start, end;
  double radius = 0.0;
  int parent = -1;  // 0-based row, -1 = root
};

std::string tree_file(const std::string& name) {
  return (fs::path(RAMIFORM_SOURCE_DIR) / ".." / "shared" / "data" / "trees" / name).string();
}

#define REQUIRE_TREE(path)                                                                     \
  if (!fs::exists(path)) {                                                                     \
    GTEST_SKIP() << "../shared/data/trees is not present (no " << (path) << "); skipping the " \
                 << "real cylinder-model check";                                               \
  }

// An independent reading of the files (plain streams), to check the importer against.
std::vector<RealCylinder> read_real(const std::string& path, bool csv) {
  std::ifstream in(path);
  std::string line;
  std::vector<RealCylinder> out;
  if (csv) std::getline(in, line);
  while (std::getline(in, line)) {
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    if (csv) std::replace(line.begin(), line.end(), ',', ' ');
    std::istringstream f(line);
    std::vector<double> v;
    double x = 0;
    while (f >> x) v.push_back(x);
    RealCylinder c;
    if (csv) {  // ID parentID startXYZ endXYZ radius ...
      c.parent = static_cast<int>(v[1]);
      c.start = {v[2], v[3], v[4]};
      c.end = {v[5], v[6], v[7]};
      c.radius = v[8];
    } else {  // radius length startXYZ axisXYZ parent(1-based) ...
      c.radius = v[0];
      c.start = {v[2], v[3], v[4]};
      c.end = c.start + v[1] * Vec3(v[5], v[6], v[7]).normalized();
      c.parent = static_cast<int>(v[8]) - 1;
    }
    out.push_back(c);
  }
  return out;
}

void check_real_model(const std::string& path, bool csv, std::size_t expected_cylinders) {
  QsmImportReport r;
  const Skeleton s = csv ? read_simpleforest(path, &r) : read_treeqsm(path, &r);
  const std::vector<RealCylinder> cyl = read_real(path, csv);
  ASSERT_EQ(cyl.size(), expected_cylinders);
  EXPECT_EQ(r.cylinders, expected_cylinders);
  EXPECT_EQ(r.reattached, 0U);  // both files name a valid parent for every cylinder
  EXPECT_EQ(s.edge_count() + 1, s.node_count());  // one tree
  expect_counts_add_up(s, r);
  // Plausible size: about one node per cylinder, plus connectors and splits.
  EXPECT_GE(s.node_count(), expected_cylinders * 9 / 10);
  EXPECT_LE(s.node_count(), expected_cylinders * 2 + 1);
  // Every cylinder end is on the skeleton (up to the merge tolerance); every start is within the
  // join tolerance of its parent's axis, which the skeleton follows to within half a radius.
  double worst_end = 0.0;
  double worst_start = 0.0;
  for (const RealCylinder& c : cyl) {
    const double rp = c.parent >= 0 ? cyl[static_cast<std::size_t>(c.parent)].radius : c.radius;
    const double scale = std::max(c.radius, rp);
    worst_end = std::max(worst_end, distance_to_skeleton(s, c.end) / c.radius);
    worst_start = std::max(worst_start, distance_to_skeleton(s, c.start) / scale);
  }
  EXPECT_LE(worst_end, 0.25 + 1e-9) << path;
  EXPECT_LE(worst_start, 1.0) << path;
  // A round trip through skeleton JSON keeps it.
  const Skeleton back = parse_skeleton_json(skeleton_to_json(s), "mem.json");
  EXPECT_EQ(back.edges, s.edges);
  std::cout << "[ info     ] " << fs::path(path).filename().string() << ": " << r.cylinders
            << " cylinders -> " << s.node_count() << " nodes, " << s.edge_count()
            << " edges; merged " << r.merged_tiny << ", split " << r.split_parents
            << ", connectors " << r.connectors << ", reattached " << r.reattached << ", duplicates "
            << r.duplicates << "; worst start " << worst_start << " r, worst end " << worst_end
            << " r\n";
}

TEST(QsmRealData, TreeQsmArchiTree) {
  const std::string path = tree_file("archi_Tree_1_TreeQSM.txt");
  REQUIRE_TREE(path);
  check_real_model(path, false, 2271);  // NOTICE.md: 2,271 cylinders
}

TEST(QsmRealData, SimpleForestCoffeetree) {
  const std::string path = tree_file("rtwig_QSM.csv");
  REQUIRE_TREE(path);
  check_real_model(path, true, 1149);  // NOTICE.md: 1,149 cylinders
  // Every child starts exactly at its parent's end: the nodes are the cylinder ends plus the root.
  QsmImportReport r;
  const Skeleton s = read_simpleforest(path, &r);
  EXPECT_EQ(s.node_count(), 1150U);
  EXPECT_EQ(r.connectors + r.split_parents + r.merged_tiny + r.duplicates, 0U);
}

}  // namespace
}  // namespace ramiform
