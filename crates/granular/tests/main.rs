mod dsmc;
