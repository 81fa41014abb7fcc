// obs2sf: turn carmen2rawlog's observation-only rawlog into an Actions/SensoryFrame
// rawlog (what rbpf-slam needs; icp-slam accepts both) and restore the scan timestamps.
//
// carmen2rawlog (MRPT 2.5.8) writes per FLASER line: CObservationOdometry (the FLASER
// odom pose) then CObservation2DRangeScan, but its timestamps are broken
// (base + 1e-6*ipc_timestamp microseconds => all equal). This tool gives the n-th
// (odometry, scan) pair the n-th FLASER ipc_timestamp (read from a text file, one per
// line), and emits per scan: CActionCollection{CActionRobotMovement2D(odometry increment
// since the previous scan, MRPT default motion model)} + CSensoryFrame{scan}.
//
// usage: obs2sf in_obs.rawlog times.txt out_sf.rawlog
#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/io/CFileGZOutputStream.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/serialization/CArchive.h>
#include <mrpt/system/datetime.h>
#include <mrpt/core/exceptions.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <vector>

using namespace mrpt;
using namespace mrpt::obs;
using namespace mrpt::poses;

int main(int argc, char** argv)
{
	if (argc != 4)
	{
		std::cerr << "usage: obs2sf in_obs.rawlog times.txt out_sf.rawlog\n";
		return 2;
	}
	try
	{
		std::vector<double> times;
		{
			std::ifstream f(argv[2]);
			double t;
			while (f >> t) times.push_back(t);
		}
		mrpt::io::CFileGZInputStream fin(argv[1]);
		mrpt::io::CFileGZOutputStream fout(argv[3]);
		auto ain = mrpt::serialization::archiveFrom(fin);
		auto aout = mrpt::serialization::archiveFrom(fout);

		CActionRobotMovement2D::TMotionModelOptions mm;  // MRPT defaults
		bool haveOdo = false, havePrevOdo = false;
		CPose2D odo, prevOdo;
		size_t nScans = 0;
		for (;;)
		{
			mrpt::serialization::CSerializable::Ptr obj;
			try
			{
				ain >> obj;
			}
			catch (mrpt::serialization::CExceptionEOF&)
			{
				break;
			}
			catch (std::exception&)
			{
				break;  // EOF of gz stream
			}
			if (auto o = std::dynamic_pointer_cast<CObservationOdometry>(obj))
			{
				odo = o->odometry;
				haveOdo = true;
				continue;
			}
			auto scan = std::dynamic_pointer_cast<CObservation2DRangeScan>(obj);
			if (!scan) continue;
			if (nScans >= times.size())
				throw std::runtime_error("more scans than timestamps");
			const auto ts = mrpt::Clock::fromDouble(times[nScans]);
			if (nScans == 0)
				fprintf(
					stderr,
					"obs2sf: first scan: %u rays, aperture %.4f deg, maxRange %.2f, "
					"sensorPose %s\n",
					unsigned(scan->getScanSize()), scan->aperture * 180.0 / M_PI,
					scan->maxRange, scan->sensorPose.asString().c_str());
			scan->timestamp = ts;
			ASSERT_(haveOdo);
			const CPose2D inc = havePrevOdo ? (odo - prevOdo) : CPose2D(0, 0, 0);
			prevOdo = odo;
			havePrevOdo = true;

			CActionRobotMovement2D act;
			act.computeFromOdometry(inc, mm);
			act.timestamp = ts;
			CActionCollection acts;
			acts.insert(act);
			CSensoryFrame sf;
			sf.insert(scan);
			aout << acts << sf;
			nScans++;
		}
		fprintf(
			stderr, "obs2sf: %zu scans written (%zu timestamps given)\n", nScans,
			times.size());
		if (nScans != times.size())
			throw std::runtime_error("scan count != timestamp count");
		return 0;
	}
	catch (const std::exception& e)
	{
		std::cerr << mrpt::exception_to_str(e) << std::endl;
		return 1;
	}
}
