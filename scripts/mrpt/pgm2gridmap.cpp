// pgm2gridmap: ROS map_server map (.yaml + binary PGM) -> MRPT .gridmap (what pf-localization's
// map_file accepts besides .simplemap), in the same world frame.
// map_server: pixel row 0 is the TOP row; origin = world (x, y) of the lower-left corner of the
// lower-left pixel; occupancy p = (255 - v) / 255 (negate 0) -> occupied if p > occupied_thresh,
// free if p < free_thresh, else unknown. MRPT cells hold p(free): occupied 0, free 1, unknown 0.5;
// MRPT cell (cx, cy) covers [x_min + cx res, x_min + (cx+1) res) x [y_min + cy res, ...).
// The grid's insertion/likelihood options are read from the pf-localization ini (section
// MetricMap_occupancyGrid_00_*), since a .gridmap carries its own options when deserialized.
// usage: pgm2gridmap map.yaml app.ini out.gridmap   (prints: x_min x_max y_min y_max res free occ)
#include <mrpt/config/CConfigFile.h>
#include <mrpt/io/CFileGZOutputStream.h>
#include <mrpt/maps/COccupancyGridMap2D.h>
#include <mrpt/serialization/CArchive.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

static std::string trim(std::string s)
{
	const auto a = s.find_first_not_of(" \t\r\"'");
	const auto b = s.find_last_not_of(" \t\r\"'");
	return a == std::string::npos ? std::string() : s.substr(a, b - a + 1);
}

int main(int argc, char** argv)
{
	if (argc != 4)
	{
		std::cerr << "usage: pgm2gridmap map.yaml app.ini out.gridmap\n";
		return 2;
	}
	try
	{
		std::string yaml = argv[1], image;
		double res = 0, ox = 0, oy = 0, occ_th = 0.65, free_th = 0.196;
		int negate = 0;
		{
			std::ifstream f(yaml);
			if (!f) throw std::runtime_error("cannot open " + yaml);
			std::string ln;
			while (std::getline(f, ln))
			{
				const auto c = ln.find(':');
				if (c == std::string::npos) continue;
				const std::string k = trim(ln.substr(0, c)), v = trim(ln.substr(c + 1));
				if (k == "image") image = v;
				else if (k == "resolution") res = std::stod(v);
				else if (k == "negate") negate = std::stoi(v);
				else if (k == "occupied_thresh") occ_th = std::stod(v);
				else if (k == "free_thresh") free_th = std::stod(v);
				else if (k == "origin")
				{
					std::string s = v;
					for (char& ch : s)
						if (ch == '[' || ch == ']' || ch == ',') ch = ' ';
					std::istringstream is(s);
					double th = 0;
					is >> ox >> oy >> th;
					if (std::abs(th) > 1e-9) throw std::runtime_error("rotated map origin not supported");
				}
			}
		}
		if (image.empty() || res <= 0) throw std::runtime_error("bad yaml " + yaml);
		if (image[0] != '/')
		{
			const auto p = yaml.find_last_of('/');
			if (p != std::string::npos) image = yaml.substr(0, p + 1) + image;
		}
		// binary PGM (P5, maxval < 256), comments allowed in the header
		std::ifstream f(image, std::ios::binary);
		if (!f) throw std::runtime_error("cannot open " + image);
		auto token = [&f]() {
			std::string t;
			char ch;
			while (f.get(ch))
			{
				if (ch == '#')
				{
					std::string rest;
					std::getline(f, rest);
					continue;
				}
				if (std::isspace(static_cast<unsigned char>(ch)))
				{
					if (!t.empty()) break;
					continue;
				}
				t += ch;
			}
			return t;
		};
		if (token() != "P5") throw std::runtime_error("not a binary PGM: " + image);
		const int W = std::stoi(token()), H = std::stoi(token()), maxv = std::stoi(token());
		if (maxv > 255) throw std::runtime_error("16-bit PGM not supported");
		std::vector<unsigned char> px(size_t(W) * H);
		f.read(reinterpret_cast<char*>(px.data()), px.size());
		if (size_t(f.gcount()) != px.size()) throw std::runtime_error("short PGM");

		mrpt::maps::COccupancyGridMap2D grid;
		mrpt::config::CConfigFile ini(argv[2]);
		grid.insertionOptions.loadFromConfigFile(ini, "MetricMap_occupancyGrid_00_insertOpts");
		grid.likelihoodOptions.loadFromConfigFile(ini, "MetricMap_occupancyGrid_00_likelihoodOpts");
		grid.setSize(ox, ox + W * res, oy, oy + H * res, res, 0.5f);
		if (int(grid.getSizeX()) != W || int(grid.getSizeY()) != H ||
			std::abs(grid.getXMin() - ox) > 1e-4 || std::abs(grid.getYMin() - oy) > 1e-4)
		{
			fprintf(stderr, "grid %ux%u from (%f, %f), wanted %dx%d from (%f, %f)\n",
				unsigned(grid.getSizeX()), unsigned(grid.getSizeY()), grid.getXMin(),
				grid.getYMin(), W, H, ox, oy);
			throw std::runtime_error("grid geometry mismatch");
		}
		size_t nFree = 0, nOcc = 0;
		for (int r = 0; r < H; r++)
			for (int c = 0; c < W; c++)
			{
				double p = double(px[size_t(r) * W + c]) / maxv;
				if (!negate) p = 1.0 - p;  // p: occupancy probability
				const int cy = H - 1 - r;  // PGM row 0 = top = highest y
				if (p > occ_th) { grid.setCell(c, cy, 0.0f); nOcc++; }
				else if (p < free_th) { grid.setCell(c, cy, 1.0f); nFree++; }
				else grid.setCell(c, cy, 0.5f);
			}
		mrpt::io::CFileGZOutputStream out(argv[3]);
		auto arch = mrpt::serialization::archiveFrom(out);
		arch << grid;
		printf("%.6f %.6f %.6f %.6f %.6f %zu %zu\n", grid.getXMin(), grid.getXMax(),
			grid.getYMin(), grid.getYMax(), grid.getResolution(), nFree, nOcc);
		return 0;
	}
	catch (const std::exception& e)
	{
		std::cerr << "pgm2gridmap: " << e.what() << std::endl;
		return 1;
	}
}
