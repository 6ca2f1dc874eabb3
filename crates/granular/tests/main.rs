mod intruder;
